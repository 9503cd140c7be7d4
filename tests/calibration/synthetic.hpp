#pragma once
// Synthetic measurements for calibration tests and benchmarks: a known ("true") model evaluated
// on a grid of points and tools, optionally seen through a rotated/shifted instrument frame, plus
// Gaussian noise.

#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

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
  set.hasDirection = options.directions.size() > 1 ||
                     options.directions.front() != model::Directions{};
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
            m.errorMm += Eigen::Vector3d(noise(generator), noise(generator), noise(generator));
          }
          if (options.withAngles) {
            m.angularErrorRad = error.angularErrorRad;
            if (options.angleNoiseRad > 0.0) {
              m.angularErrorRad += Eigen::Vector3d(angleNoise(generator), angleNoise(generator),
                                                   angleNoise(generator));
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

}  // namespace volcomp::calibration::testing
