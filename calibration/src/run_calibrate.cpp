#include "volcomp/calibration/run_calibrate.hpp"

#include <filesystem>
#include <ostream>

#include "volcomp/calibration/measurements.hpp"
#include "volcomp/calibration/report.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::calibration {
namespace {

using config::ConfigError;

// Option errors are reported like file errors ("command line: --loss: ..."), exit status 2.
constexpr const char* kCommandLine = "command line";

/// Written whole or not at all, never over an input (output::writeOutputFile).
void writeJsonFile(const std::string& path, const nlohmann::json& document,
                   const CalibrateOptions& options) {
  output::writeOutputFile(path, document.dump(2) + '\n',
                          {options.templatePath, options.measurementsPath});
}

}  // namespace

int runCalibrate(const CalibrateOptions& options, std::ostream& out) {
  SolveOptions solveOptions;
  if (options.loss == "huber") {
    solveOptions.loss = RobustLoss::Huber;
  } else if (options.loss == "cauchy") {
    solveOptions.loss = RobustLoss::Cauchy;
  } else if (options.loss != "none") {
    throw ConfigError(kCommandLine, "--loss",
                      "expected none, huber or cauchy, got " + options.loss);
  }
  if (options.method != "auto" && options.method != "linear" && options.method != "lm") {
    throw ConfigError(kCommandLine, "--method",
                      "expected auto, linear or lm, got " + options.method);
  }
  if (!(options.lossScaleMm > 0.0)) throw ConfigError(kCommandLine, "--loss-scale", "expected > 0");
  if (!(options.rankTolerance > 0.0 && options.rankTolerance < 1.0)) {
    throw ConfigError(kCommandLine, "--rank-tol", "expected a value in (0, 1)");
  }
  if (options.method == "linear" && solveOptions.loss != RobustLoss::None) {
    throw ConfigError(kCommandLine, "--loss", "a robust loss needs --method lm (or auto)");
  }
  // Refused before the work rather than after it; writeJsonFile checks again.
  output::refuseInputAsOutput(options.outPath, {options.templatePath, options.measurementsPath});
  if (!options.reportPath.empty()) {
    output::refuseInputAsOutput(options.reportPath,
                                {options.templatePath, options.measurementsPath});
    std::error_code ec;
    if (std::filesystem::weakly_canonical(options.outPath, ec) ==
        std::filesystem::weakly_canonical(options.reportPath, ec)) {
      throw ConfigError(kCommandLine, "--report", "names the same file as --out");
    }
  }
  solveOptions.lossScale = options.lossScaleMm;
  solveOptions.rankTolerance = options.rankTolerance;
  solveOptions.maxIterations = options.maxIterations;
  solveOptions.progress = [&out](const std::string& line) { out << "  " << line << std::endl; };

  config::ParseOptions parseOptions;
  parseOptions.allowIdentify = true;
  const config::ModelDocument document = config::loadModelFile(options.templatePath, parseOptions);
  if (document.identify.empty()) {
    throw ConfigError(options.templatePath, "components",
                      "nothing to identify: mark components with {\"identify\": ...}");
  }
  const MeasurementSet measurements = readMeasurementsCsv(options.measurementsPath);
  out << "read " << measurements.points.size() << " points from " << options.measurementsPath
      << std::endl;
  const auto problem = makeIdentificationProblem(document, measurements, options.identification);
  if (problem->rowCount() < problem->parameterCount()) {
    out << "warning: " << problem->rowCount() << " equations for " << problem->parameterCount()
        << " parameters: some combinations cannot be identified" << std::endl;
  }
  const bool linear =
      options.method == "linear" || (options.method == "auto" && problem->nearlyLinear() &&
                                     solveOptions.loss == RobustLoss::None);
  solveOptions.method = linear ? Method::Linear : Method::LevenbergMarquardt;
  out << "identifying " << problem->parameterCount() << " parameters ("
      << (linear ? "linear identification" : "Levenberg-Marquardt") << ")" << std::endl;

  const FitResult fit = solve(*problem, problem->startVector(), solveOptions);

  ReportContext context;
  context.templateFile = options.templatePath;
  context.measurementFile = options.measurementsPath;
  context.method = linear ? "linear" : "levenberg-marquardt";
  context.loss = options.loss;
  context.rankTolerance = options.rankTolerance;
  for (const Measurement& m : measurements.points) context.lines.push_back(m.line);

  nlohmann::json model = problem->modelJson(fit.parameters);
  // The output must load as an ordinary model file; check it before writing.
  config::parseModel(model, options.outPath);
  writeJsonFile(options.outPath, model, options);
  if (!options.reportPath.empty()) {
    writeJsonFile(options.reportPath, reportJson(fit, problem->parameterInfo(), context), options);
  }
  out << '\n';
  writeSummary(out, fit, problem->parameterInfo(), context);
  out << "\nmodel written to " << options.outPath;
  if (!options.reportPath.empty()) out << ", report to " << options.reportPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::calibration
