#include "planar2dof_run.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <numbers>
#include <ostream>

#include "output_files.hpp"
#include "volcomp/calibration/planar2dof.hpp"
#include "volcomp/calibration/report.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/json_reader.hpp"

namespace volcomp::calibration::detail {
namespace {

using config::ConfigError;
using config::JsonReader;
using Json = nlohmann::json;

constexpr const char* kFormat = "volcomp-planar2dof/1";
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

// The units of seed 003's table 2: device lengths in mm, the plate's rotation in degrees, the
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

struct Device {
  Planar2DofGeometry geometry;
  std::array<bool, kPlanar2DofParameterCount> free = kPaperFreeParameters;
  Planar2DofParameters start{};
  int reference = 1;  // 1-based, as the paper numbers its points
};

Device readDevice(const Json& document, const std::string& file) {
  const JsonReader root(document, file);
  root.allowOnly({"format", "name", "description", "legs_mm", "reference_point", "free", "start",
                  "values", "std", "calibration"});
  Device device;
  if (const auto legs = root.find("legs_mm")) {
    const auto v = legs->fixedNumbers<2>();
    if (!(v[0] > 0.0 && v[1] > 0.0)) legs->failExpected("two leg lengths > 0 (mm)");
    device.geometry.legAMm = v[0];
    device.geometry.legBMm = v[1];
  }
  device.reference = static_cast<int>(root.integerOr("reference_point", 1, 1 << 30, 1));
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

std::vector<Planar2DofSample> readSamples(const std::string& path, std::vector<int>& lines) {
  config::CsvSchema schema;
  schema.add({"a", "b", "gx", "gy"}, config::CsvQuantity::Length, true);
  std::ifstream input = config::CsvReader::open(path);
  config::CsvReader csv(input, path, schema);
  std::vector<Planar2DofSample> samples;
  while (csv.next()) {
    Planar2DofSample s;
    s.aMm = csv.number("a");
    s.bMm = csv.number("b");
    s.lgpMm = {csv.number("gx"), csv.number("gy")};
    samples.push_back(s);
    lines.push_back(static_cast<int>(csv.line()));
  }
  if (samples.size() < 2) throw ConfigError(path, "", "expected at least 2 readings");
  return samples;
}

// Mean length of the 2-D deviations dL_i (seed 003's "average deviation").
double meanDeviation(const Planar2DofProblem& problem, const Eigen::VectorXd& p) {
  double sum = 0.0;
  double r[2];
  for (int i = 0; i < problem.observationCount(); ++i) {
    problem.observationResiduals(p.data(), i, r);
    sum += std::hypot(r[0], r[1]);
  }
  return sum / problem.observationCount();
}

// Seed 003's s_r: the standard deviation of the computed position r'_i = R(phi)(r_i - r_ref) +
// e_K through all parameter variances and covariances, |sigma| of the 2-D vector, RMS over the
// points.
double positionStd(const Planar2DofProblem& problem, const FitResult& fit) {
  Eigen::MatrixXd jacobian;
  problem.jacobian(fit.parameters, jacobian);
  const Eigen::MatrixXd propagated = jacobian * fit.statistics.rangeFactor;
  return std::sqrt(fit.statistics.varianceFactor * propagated.squaredNorm() /
                   problem.observationCount());
}

void writeTable(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info) {
  out << std::left << std::setw(12) << "Parameters" << std::right << std::setw(18)
      << "Starting values" << std::setw(18) << "Optimized values" << std::setw(24)
      << "Standard deviation s_i"
      << "\n";
  for (std::size_t j = 0; j < info.size(); ++j) {
    const auto index = static_cast<Eigen::Index>(j);
    const std::string unit = info[j].unit == "deg"
                                 ? "°"
                                 : " " + (info[j].unit == "um" ? std::string("µm") : info[j].unit);
    const auto cell = [&](double value, int digits) {
      return std::isfinite(value) ? significant(value * info[j].toDisplay, digits) + unit
                                  : std::string("not identifiable");
    };
    out << std::left << std::setw(12) << info[j].name << std::right << std::setw(18)
        << cell(fit.start(index), 4) << std::setw(18) << cell(fit.parameters(index), 4)
        << std::setw(24) << cell(fit.statistics.standardDeviation(index), 2) << "\n";
  }
}

void writeCorrelations(std::ostream& out, const FitResult& fit,
                       const std::vector<ParameterInfo>& info) {
  out << "\ncorrelations:\n" << std::setw(6) << "";
  for (const ParameterInfo& p : info) out << std::setw(7) << p.name;
  out << "\n";
  for (std::size_t i = 0; i < info.size(); ++i) {
    out << std::left << std::setw(6) << info[i].name << std::right;
    for (std::size_t j = 0; j < info.size(); ++j) {
      const double c =
          fit.statistics.correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      std::ostringstream cell;
      cell << std::fixed << std::setprecision(2) << c;
      out << std::setw(7) << (std::isfinite(c) ? cell.str() : std::string("-"));
    }
    out << "\n";
  }
}

}  // namespace

bool isPlanar2DofDocument(const Json& document) {
  return document.is_object() && document.contains("format") && document.at("format") == kFormat;
}

int runPlanar2Dof(const Json& document, const CalibrateOptions& options, std::ostream& out) {
  const Device device = readDevice(document, options.templatePath);
  std::vector<int> lines;
  const std::vector<Planar2DofSample> samples = readSamples(options.measurementsPath, lines);
  if (device.reference > static_cast<int>(samples.size())) {
    throw ConfigError(options.templatePath, "reference_point",
                      "expected a reading number 1.." + std::to_string(samples.size()));
  }
  out << "read " << samples.size() << " readings from " << options.measurementsPath
      << " (reference point " << device.reference << ")" << std::endl;
  const Planar2DofProblem problem(device.geometry, samples, device.reference - 1, device.free,
                                  device.start);
  std::vector<ParameterInfo> info;
  for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
    if (device.free[static_cast<std::size_t>(j)]) info.push_back(infoOf(j));
  }
  SolveOptions solveOptions;
  solveOptions.method = Method::LevenbergMarquardt;
  solveOptions.rankTolerance = options.rankTolerance;
  solveOptions.maxIterations = options.maxIterations;
  const FitResult fit = solve(problem, problem.freeVector(device.start), solveOptions);

  ReportContext context;
  context.kind = "planar2dof";
  context.templateFile = options.templatePath;
  context.measurementFile = options.measurementsPath;
  context.method = "levenberg-marquardt";
  context.loss = "none";
  context.rankTolerance = options.rankTolerance;
  context.lines = lines;
  context.volcompVersion = options.volcompVersion;
  context.date = utcNow();
  const double sr = positionStd(problem, fit);
  const double before = meanDeviation(problem, problem.freeVector(device.start));
  const double after = meanDeviation(problem, fit.parameters);

  out << "\n"
      << (fit.converged ? "converged" : "NOT converged") << " after " << fit.iterations
      << " iterations (Levenberg-Marquardt): " << fit.termination << "\n\n";
  writeTable(out, fit, info);
  writeCorrelations(out, fit, info);
  out << "\ns_r (standard deviation of the position through all parameter variances and "
         "covariances, RMS over the points): "
      << significant(sr * 1e3, 3) << " µm\n"
      << "mean deviation |dL| between device and grid plate: " << significant(before * 1e3, 4)
      << " µm before, " << significant(after * 1e3, 3) << " µm after the fit\n"
      << "s0 " << significant(std::sqrt(fit.statistics.varianceFactor) * 1e3, 3) << " µm, rank "
      << fit.statistics.rank << " of " << fit.statistics.parameterCount << "\n";
  if (!fit.statistics.unidentifiable.empty()) {
    out << "\nnot identifiable with these data:\n";
    for (const Combination& c : fit.statistics.unidentifiable) {
      out << "  - " << c.description << "\n";
    }
  }

  Json deviceOut = document;
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
  deviceOut["values"] = values;
  deviceOut["std"] = stds;
  const std::vector<std::filesystem::path> inputs{options.templatePath, options.measurementsPath};
  writeJsonFile(options.outPath, deviceOut, inputs);
  if (!options.reportPath.empty()) {
    Json report = reportJson(fit, info, context);
    report["s_r_mm"] = sr;
    report["mean_deviation_mm"] = {{"before", before}, {"after", after}};
    writeJsonFile(options.reportPath, report, inputs);
  }
  out << "\ndevice written to " << options.outPath;
  if (!options.reportPath.empty()) out << ", report to " << options.reportPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::calibration::detail
