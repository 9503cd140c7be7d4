#pragma once
// Synthetic measurements for calibration tests and benchmarks: a known ("true") model evaluated
// on a grid of points and tools, optionally seen through a rotated/shifted instrument frame, plus
// Gaussian noise.

#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "random_draws.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::calibration::testing {

struct SyntheticOptions {
  std::vector<double> x{0, 200, 400, 600, 800};
  std::vector<double> y{0, 125, 250, 375, 500};
  std::vector<double> z{-400, -250, -100, 0};
  std::vector<Eigen::Vector3d> tools{Eigen::Vector3d(0, 0, 100)};
  double noiseMm = 0.0;
  unsigned seed = 1;
  /// Instrument frame: rotation (rad, Rz Ry Rx) and translation (mm).
  Eigen::Vector3d frameRotationRad = Eigen::Vector3d::Zero();
  Eigen::Vector3d frameTranslationMm = Eigen::Vector3d::Zero();
  /// Also "measure" the angular error (ea, eb, ec), with noise angleNoiseRad (no frame rotation).
  bool withAngles = false;
  double angleNoiseRad = 0.0;
  /// Every point is measured once per entry, approached in those directions (recorded in the
  /// measurement's direction column).
  std::vector<model::Directions> directions{model::Directions{}};
};

/// FXYZ, tool [0, 0, 100], travel 0..800 x 0..500 x -400..0 mm (the synthetic points' box: a
/// polynomial needs the travel it holds over): EXX 3 um + 0.012 um/mm, EBX 25 urad (pitch: Abbe
/// error with the tool length), EXZ -0.02 um/mm (zero at 0), EC0Y 15 urad.
inline nlohmann::json fxyzTruth() {
  return nlohmann::json{{"format", "volcomp-model/1"},
                        {"topology", "FXYZ"},
                        {"travel", {{"X", {0, 800}}, {"Y", {0, 500}}, {"Z", {-400, 0}}}},
                        {"tool", {0, 0, 100}},
                        {"error_units", {{"length", "um"}, {"angle", "urad"}}},
                        {"components",
                         {{"EXX", {{"polynomial", {3.0, 0.012}}}},
                          {"EBX", 25.0},
                          {"EXZ", {{"polynomial", {0.0, -0.02}}}},
                          {"EC0Y", 15.0}}}};
}

/// fxyzTruth() with every component to identify: EXX linear, EBX constant, EXZ linear with
/// zero_at 0, EC0Y constant (5 parameters).
inline nlohmann::json fxyzTemplate() {
  nlohmann::json t = fxyzTruth();
  t["components"] = {
      {"EXX", {{"identify", {{"basis", "polynomial"}, {"degree", 1}}}}},
      {"EBX", {{"identify", "constant"}}},
      {"EXZ", {{"identify", {{"basis", "polynomial"}, {"degree", 1}, {"zero_at", 0}}}}},
      {"EC0Y", {{"identify", "constant"}}}};
  return t;
}

/// A rows x columns matrix of standard normal entries (reproducible per seed).
inline Eigen::MatrixXd randomMatrix(int rows, int columns, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd m(rows, columns);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < columns; ++j) m(i, j) = normal(generator);
  }
  return m;
}

inline model::MachineModelSpec machineSpec(const nlohmann::json& document) {
  return std::get<model::MachineModelSpec>(config::parseModel(document, "truth.json").spec);
}

inline config::ModelDocument templateDocument(const nlohmann::json& document) {
  config::ParseOptions options;
  options.allowIdentify = true;
  return config::parseModel(document, "template.json", options);
}

inline MeasurementSet simulate(const model::MachineModelSpec& truth,
                               const SyntheticOptions& options) {
  const model::MachineModel model(truth);
  model::Workspace ws;
  std::mt19937 generator(options.seed);
  std::normal_distribution<double> noise(0.0, options.noiseMm);
  const Eigen::Matrix3d rotation = model::rotationZYX(
      options.frameRotationRad.x(), options.frameRotationRad.y(), options.frameRotationRad.z());
  MeasurementSet set;
  set.file = "synthetic.csv";
  set.hasTool = true;
  set.hasAngles = options.withAngles;
  set.hasDirection =
      options.directions.size() > 1 || options.directions.front() != model::Directions{};
  std::normal_distribution<double> angleNoise(0.0, options.angleNoiseRad);
  int line = 2;
  for (const model::Directions& directions : options.directions) {
    for (const Eigen::Vector3d& tool : options.tools) {
      for (double x : options.x) {
        for (double y : options.y) {
          for (double z : options.z) {
            Measurement m;
            m.qMm = {x, y, z};
            m.toolMm = tool;
            m.directions = directions;
            const model::PointError error = model::evaluate(model, ws, m.qMm, tool, directions);
            const Eigen::Vector3d nominal = m.qMm + tool - truth.workpieceMm;
            m.errorMm = rotation * (nominal + error.errorMm) + options.frameTranslationMm - nominal;
            if (options.noiseMm > 0.0) {
              m.errorMm += testutil::draw3(noise, generator);
            }
            if (options.withAngles) {
              m.angularErrorRad = error.angularErrorRad;
              if (options.angleNoiseRad > 0.0) {
                m.angularErrorRad += testutil::draw3(angleNoise, generator);
              }
            }
            m.line = line++;
            set.points.push_back(m);
          }
        }
      }
    }
  }
  return set;
}

/// fxyzTruth() measured as `options` say, and fxyzTemplate() fitted to it (linear method).
struct FxyzFit {
  std::unique_ptr<IdentificationProblem> problem;
  FitResult fit;
};
inline FxyzFit fitFxyz(const SyntheticOptions& options) {
  FxyzFit result;
  result.problem = makeIdentificationProblem(templateDocument(fxyzTemplate()),
                                             simulate(machineSpec(fxyzTruth()), options));
  result.fit = solve(*result.problem, result.problem->startVector());
  return result;
}

}  // namespace volcomp::calibration::testing
