#include "planar2dof_verb.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "calibration_files.hpp"
#include "volcomp/calibration/planar2dof_device.hpp"
#include "volcomp/calibration/report.hpp"

namespace volcomp::cli {
namespace {

using Json = nlohmann::json;

void writeTable(std::ostream& out, const calibration::FitResult& fit,
                const std::vector<calibration::ParameterInfo>& info) {
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
      return std::isfinite(value)
                 ? calibration::significant(value * info[j].toDisplay, digits) + unit
                 : std::string("not identifiable");
    };
    out << std::left << std::setw(12) << info[j].name << std::right << std::setw(18)
        << cell(fit.start(index), 4) << std::setw(18) << cell(fit.parameters(index), 4)
        << std::setw(24) << cell(fit.statistics.standardDeviation(index), 2) << "\n";
  }
}

void writeCorrelations(std::ostream& out, const calibration::FitResult& fit,
                       const std::vector<calibration::ParameterInfo>& info) {
  out << "\ncorrelations:\n" << std::setw(6) << "";
  for (const calibration::ParameterInfo& p : info) out << std::setw(7) << p.name;
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

int runPlanar2Dof(const Json& document, const CalibrateOptions& options, std::ostream& out) {
  const calibration::Planar2DofDevice device =
      calibration::readPlanar2DofDevice(document, options.templatePath);
  const calibration::Planar2DofReadings readings =
      calibration::readPlanar2DofReadings(options.measurementsPath);
  const calibration::Planar2DofCalibration result = calibration::calibratePlanar2Dof(
      document, options.templatePath, device, readings, options.settings);
  const calibration::FitResult& fit = result.fit;
  const std::vector<calibration::ParameterInfo>& info = result.parameters;
  out << "read " << readings.samples.size() << " readings from " << options.measurementsPath
      << " (reference point " << device.referencePoint << ")" << std::endl;

  calibration::ReportContext context;
  context.kind = calibration::ReportKind::Planar2Dof;
  context.templateFile = options.templatePath;
  context.measurementFile = options.measurementsPath;
  context.method = calibration::Method::LevenbergMarquardt;
  context.loss = calibration::RobustLoss::None;
  context.rankTolerance = options.settings.rankTolerance;
  context.lines = readings.lines;
  context.volcompVersion = options.volcompVersion;
  context.date = utcNow();
  const double sr = result.positionStdMm;
  const double before = result.meanDeviationBeforeMm;
  const double after = result.meanDeviationAfterMm;

  out << "\n"
      << (fit.converged ? "converged" : "NOT converged") << " after " << fit.iterations
      << " iterations (Levenberg-Marquardt): " << fit.termination << "\n\n";
  writeTable(out, fit, info);
  writeCorrelations(out, fit, info);
  out << "\ns_r (standard deviation of the position through all parameter variances and "
         "covariances, RMS over the points): "
      << calibration::significant(sr * 1e3, 3) << " µm\n"
      << "mean deviation |dL| between device and grid plate: "
      << calibration::significant(before * 1e3, 4) << " µm before, "
      << calibration::significant(after * 1e3, 3) << " µm after the fit\n"
      << "s0 " << calibration::significant(std::sqrt(fit.statistics.varianceFactor) * 1e3, 3)
      << " µm, rank " << fit.statistics.rank << " of " << fit.statistics.parameterCount << "\n";
  if (!fit.statistics.unidentifiable.empty()) {
    out << "\nnot identifiable with these data:\n";
    for (const calibration::Combination& c : fit.statistics.unidentifiable) {
      out << "  - " << c.description << "\n";
    }
  }

  const std::vector<std::filesystem::path> inputs{options.templatePath, options.measurementsPath};
  writeJsonFile(options.outPath, result.fittedDevice, inputs);
  if (!options.reportPath.empty()) {
    Json report = calibration::reportJson(fit, info, context);
    report["s_r_mm"] = sr;
    report["mean_deviation_mm"] = {{"before", before}, {"after", after}};
    writeJsonFile(options.reportPath, report, inputs);
  }
  out << "\ndevice written to " << options.outPath;
  if (!options.reportPath.empty()) out << ", report to " << options.reportPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::cli
