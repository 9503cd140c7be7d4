#include "volcomp/calibration/planar2dof_device.hpp"

#include <cmath>
#include <fstream>
#include <numbers>

#include "volcomp/calibration/planar2dof.hpp"
#include "volcomp/calibration/report.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/json_reader.hpp"

namespace volcomp::calibration {
namespace {

using config::ConfigError;
using config::JsonReader;
using Json = nlohmann::json;

constexpr const char* kFormat = "volcomp-planar2dof/1";
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// The units of Hanak, Zirn and Ruoff's table 2: device lengths in mm, the plate's rotation in degrees, the
// reference point's offsets in um. The device file gives every value in mm, phi in degrees.
ParameterInfo infoOf(int j) {
  const std::string name = planar2DofName(j);
  if (j == phi) return {name, "start." + name, "deg", kRadToDeg, false};
  if (j == exK || j == eyK) return {name, "start." + name, "um", 1e3, false};
  return {name, "start." + name, "mm", 1.0, false};
}

double fileToInternal(int j) {
  return j == phi ? 1.0 / kRadToDeg : 1.0;
}
}  // namespace

Planar2DofDevice readPlanar2DofDevice(const Json& document, const std::string& file) {
  const JsonReader root(document, file);
  root.allowOnly({"format", "name", "description", "legs_mm", "reference_point", "free", "start",
                  "values", "std", "calibration"});
  Planar2DofDevice device;
  if (const auto legs = root.find("legs_mm")) {
    const auto v = legs->fixedNumbers<2>();
    if (!(v[0] > 0.0 && v[1] > 0.0)) legs->failExpected("two leg lengths > 0 (mm)");
    device.geometry.legAMm = v[0];
    device.geometry.legBMm = v[1];
  }
  device.referencePoint = static_cast<int>(root.integerOr("reference_point", 1, 1 << 30, 1));
  if (const auto free = root.find("free")) {
    if (free->isString() && free->string() == "all") {
      device.free.fill(true);
    } else {
      device.free.fill(false);
      for (const JsonReader& name : free->elements(1)) {
        bool known = false;
        for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
          if (name.isString() && name.string() == planar2DofName(j)) {
            device.free[static_cast<std::size_t>(j)] = true;
            known = true;
          }
        }
        if (!known) name.failExpected("one of eLa, eLb, ea, eha, eb, ehb, phi, exK, eyK");
      }
    }
  }
  if (const auto start = root.find("start")) {
    start->expectObject();
    for (const auto& [key, value] : start->members()) {
      bool known = false;
      for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
        if (key == planar2DofName(j)) {
          device.start[static_cast<std::size_t>(j)] = value.number() * fileToInternal(j);
          known = true;
        }
      }
      if (!known)
        value.fail("unknown parameter; expected eLa, eLb, ea, eha, eb, ehb, phi, exK, eyK");
    }
  }
  return device;
}

Planar2DofReadings readPlanar2DofReadings(const std::string& path) {
  config::CsvSchema schema;
  schema.add({"a", "b", "gx", "gy"}, config::CsvQuantity::Length, true);
  std::ifstream input = config::CsvReader::open(path);
  config::CsvReader csv(input, path, schema);
  Planar2DofReadings readings;
  while (csv.next()) {
    Planar2DofSample s;
    s.aMm = csv.number("a");
    s.bMm = csv.number("b");
    s.lgpMm = {csv.number("gx"), csv.number("gy")};
    readings.samples.push_back(s);
    readings.lines.push_back(static_cast<int>(csv.line()));
  }
  if (readings.samples.size() < 2) throw ConfigError(path, "", "expected at least 2 readings");
  return readings;
}

namespace {

// Mean length of the 2-D deviations dL_i (Hanak, Zirn and Ruoff's "average deviation").
double meanDeviation(const Planar2DofProblem& problem, const Eigen::VectorXd& p) {
  double sum = 0.0;
  double r[2];
  for (int i = 0; i < problem.observationCount(); ++i) {
    problem.observationResiduals(p.data(), i, r);
    sum += std::hypot(r[0], r[1]);
  }
  return sum / problem.observationCount();
}

// Hanak, Zirn and Ruoff's s_r: the standard deviation of the computed position r'_i = R(phi)(r_i - r_ref) +
// e_K through all parameter variances and covariances, |sigma| of the 2-D vector, RMS over the
// points.
double positionStd(const Planar2DofProblem& problem, const FitResult& fit) {
  Eigen::MatrixXd jacobian;
  problem.jacobian(fit.parameters, jacobian);
  const Eigen::MatrixXd propagated = jacobian * fit.statistics.rangeFactor;
  return std::sqrt(fit.statistics.varianceFactor * propagated.squaredNorm() /
                   problem.observationCount());
}

}  // namespace

bool isPlanar2DofDocument(const Json& document) {
  return document.is_object() && document.contains("format") && document.at("format") == kFormat;
}

Planar2DofCalibration calibratePlanar2Dof(const Json& document, const std::string& file,
                                          const Planar2DofDevice& device,
                                          const Planar2DofReadings& readings,
                                          const CalibrationSettings& settings) {
  if (device.referencePoint > static_cast<int>(readings.samples.size())) {
    throw ConfigError(file, "reference_point",
                      "expected a reading number 1.." + std::to_string(readings.samples.size()));
  }
  const Planar2DofProblem problem(device.geometry, readings.samples, device.referencePoint - 1,
                                  device.free, device.start);
  Planar2DofCalibration result;
  std::vector<ParameterInfo>& info = result.parameters;
  for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
    if (device.free[static_cast<std::size_t>(j)]) info.push_back(infoOf(j));
  }
  // The device is nonlinear in its parameters (circle intersections): Levenberg-Marquardt,
  // without a robust loss (Hanak, Zirn and Ruoff's least squares).
  SolveOptions solveOptions;
  solveOptions.method = Method::LevenbergMarquardt;
  solveOptions.rankTolerance = settings.rankTolerance;
  solveOptions.maxIterations = settings.maxIterations;
  result.fit = solve(problem, problem.freeVector(device.start), solveOptions);
  const FitResult& fit = result.fit;
  result.positionStdMm = positionStd(problem, fit);
  result.meanDeviationBeforeMm = meanDeviation(problem, problem.freeVector(device.start));
  result.meanDeviationAfterMm = meanDeviation(problem, fit.parameters);

  Json values = Json::object(), stds = Json::object();
  const Planar2DofParameters full = problem.full(fit.parameters.data());
  for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
    values[planar2DofName(j)] = full[static_cast<std::size_t>(j)] / fileToInternal(j);
  }
  for (std::size_t k = 0; k < info.size(); ++k) {
    const double s = fit.statistics.standardDeviation(static_cast<Eigen::Index>(k));
    stds[info[k].name] = std::isfinite(s)
                             ? Json(s / fileToInternal(problem.fullIndex(static_cast<int>(k))))
                             : Json(nullptr);
  }
  result.fittedDevice = document;
  result.fittedDevice["values"] = values;
  result.fittedDevice["std"] = stds;
  return result;
}

}  // namespace volcomp::calibration
