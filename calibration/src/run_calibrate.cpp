#include "volcomp/calibration/run_calibrate.hpp"

#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <vector>

#include "fit_analysis.hpp"
#include "output_files.hpp"
#include "planar2dof_run.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/calibration/report.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::calibration {
namespace {

using config::ConfigError;

// Option errors are reported like file errors ("command line: --loss: ..."), exit status 2.
constexpr const char* kCommandLine = "command line";

// Every file the run reads: no output may replace one of them (volcomp::output).
std::vector<std::filesystem::path> calibrateInputs(const CalibrateOptions& options) {
  std::vector<std::filesystem::path> inputs{options.templatePath, options.measurementsPath};
  if (!options.validatePath.empty()) inputs.emplace_back(options.validatePath);
  if (!options.predictPath.empty()) inputs.emplace_back(options.predictPath);
  return inputs;
}

SolveOptions solveOptionsFrom(const CalibrateOptions& options, std::ostream& out) {
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
  // Refused before the work rather than after it; the writers check again.
  const std::vector<std::filesystem::path> inputs = calibrateInputs(options);
  output::refuseInputAsOutput(options.outPath, inputs);
  if (!options.predictOutPath.empty()) output::refuseInputAsOutput(options.predictOutPath, inputs);
  if (!options.reportPath.empty()) {
    output::refuseInputAsOutput(options.reportPath, inputs);
    std::error_code ec;
    if (std::filesystem::weakly_canonical(options.outPath, ec) ==
        std::filesystem::weakly_canonical(options.reportPath, ec)) {
      throw ConfigError(kCommandLine, "--report", "names the same file as --out");
    }
  }
  if (options.angleUnit != "urad" && options.angleUnit != "arcsec") {
    throw ConfigError(kCommandLine, "--angle-unit", "expected urad or arcsec");
  }
  if (options.folds == 1 || options.folds < 0) {
    throw ConfigError(kCommandLine, "--k-fold", "expected k >= 2");
  }
  if (options.predictPath.empty() != options.predictOutPath.empty()) {
    throw ConfigError(kCommandLine, "--predict", "--predict and --predict-out go together");
  }
  solveOptions.lossScale = options.lossScaleMm;
  solveOptions.rankTolerance = options.rankTolerance;
  solveOptions.maxIterations = options.maxIterations;
  solveOptions.progress = [&out](const std::string& line) { out << "  " << line << std::endl; };
  return solveOptions;
}

// Points to predict at: the shared CSV reader, positions with optional tool and direction.
std::vector<PointPrediction> readPredictionPoints(const std::string& path,
                                                  const Eigen::Vector3d& templateTool) {
  std::ifstream input = config::CsvReader::open(path);
  config::CsvReader csv(input, path, config::positionsSchema());
  const int direction = csv.column("direction");
  std::vector<PointPrediction> points;
  while (csv.next()) {
    PointPrediction p;
    p.qMm = {csv.number("x"), csv.number("y"), csv.number("z")};
    p.toolMm = csv.has("tx") ? Eigen::Vector3d(csv.number("tx"), csv.number("ty"), csv.number("tz"))
                             : templateTool;
    if (direction >= 0) p.directions = csv.directions(direction);
    p.line = static_cast<int>(csv.line());
    points.push_back(p);
  }
  return points;
}

void writePredictions(const std::string& path, const std::vector<PointPrediction>& points,
                      const std::vector<std::filesystem::path>& inputs) {
  std::ostringstream file;
  file.precision(17);
  file << "x,y,z,tx,ty,tz,ex,ey,ez,ux,uy,uz,k,determined\n";
  for (const PointPrediction& p : points) {
    for (const Eigen::Vector3d* v : {&p.qMm, &p.toolMm, &p.errorMm}) {
      file << v->x() + 0.0 << ',' << v->y() + 0.0 << ',' << v->z() + 0.0 << ',';
    }
    for (int axis = 0; axis < 3; ++axis) {
      // An undetermined prediction has no uncertainty to write: the field stays empty.
      if (p.determined) file << p.stdMm(axis);
      file << ',';
    }
    file << kCoverageFactor << ',' << (p.determined ? 1 : 0) << '\n';
  }
  output::writeOutputFile(path, file.str(), inputs);
}

}  // namespace

int runCalibrate(const CalibrateOptions& options, std::ostream& out) {
  SolveOptions solveOptions = solveOptionsFrom(options, out);
  const nlohmann::json templateJson = config::readJsonFile(options.templatePath);
  if (detail::isPlanar2DofDocument(templateJson)) {
    return detail::runPlanar2Dof(templateJson, options, out);
  }
  config::ParseOptions parseOptions;
  parseOptions.allowIdentify = true;
  const config::ModelDocument document =
      config::parseModel(templateJson, options.templatePath, parseOptions);
  if (document.identify.empty()) {
    throw ConfigError(options.templatePath, "components",
                      "nothing to identify: mark components with {\"identify\": ...}");
  }
  const MeasurementSet measurements = readMeasurementsCsv(options.measurementsPath);
  out << "read " << measurements.points.size() << " points from " << options.measurementsPath
      << std::endl;
  const detail::ProblemFactory factory = [&](const MeasurementSet& set) {
    return makeIdentificationProblem(document, set, options.identification);
  };
  const auto problem = factory(measurements);
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
  context.volcompVersion = options.volcompVersion;
  context.date = detail::utcNow();
  context.angleDisplay =
      options.angleUnit == "arcsec" ? AngleDisplay::Arcsecond : AngleDisplay::Microradian;
  for (const Measurement& m : measurements.points) context.lines.push_back(m.line);
  context.coverage = detail::coverageOf(measurements, document);

  const FitStatistics& st = fit.statistics;
  if (2 * st.rank < st.parameterCount && !options.force) {
    out << '\n';
    writeMissingSummary(out, fit, problem->parameterInfo(), context);
    throw ConfigError(options.measurementsPath, "",
                      "the measurements identify " + std::to_string(st.rank) + " of " +
                          std::to_string(st.parameterCount) +
                          " independent parameters: far too few, nothing written (what is "
                          "missing is above; --force writes the model anyway)");
  }

  std::vector<PointPrediction> measured = detail::measuredPoints(measurements, document);
  detail::predictPoints(*problem, fit, measured);
  context.prediction = summarise(measured);
  context.curves = detail::sampleCurves(*problem, fit);
  if (!options.validatePath.empty()) {
    context.validation =
        detail::validateWith(factory, readMeasurementsCsv(options.validatePath), fit);
  } else if (options.folds >= 2) {
    out << "cross-validating: " << options.folds << " fits, each without one fold of the points"
        << std::endl;
    context.validation = detail::crossValidate(factory, measurements, options.folds, solveOptions);
  }
  if (!options.predictPath.empty()) {
    const auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
    context.predictedAt = readPredictionPoints(
        options.predictPath, spec != nullptr ? spec->toolMm : Eigen::Vector3d::Zero());
    detail::predictPoints(*problem, fit, context.predictedAt);
  }

  config::CalibrationRecord record;
  record.volcompVersion = options.volcompVersion;
  record.date = context.date;
  record.templateFile = options.templatePath;
  record.measurementFiles = {options.measurementsPath};
  record.validationFile = options.validatePath;
  record.points = static_cast<int>(measurements.points.size());
  record.parameterCount = st.parameterCount;
  record.rank = st.rank;
  record.residualRmsBeforeMm = fit.before.rms;
  record.residualRmsAfterMm = fit.after.rms;
  if (context.validation) record.residualRmsValidationMm = context.validation->stats.rms;
  record.s0Mm = std::sqrt(st.varianceFactor);
  for (std::size_t j = 0; j < st.identifiable.size(); ++j) {
    if (!st.identifiable[j]) record.notIdentifiable.push_back(problem->parameterInfo()[j].name);
  }
  record.toolsMm = context.coverage->toolsMm;

  nlohmann::json model = problem->modelJson(fit.parameters);
  model["calibration"] = config::writeCalibrationRecord(record);
  // The output must load as an ordinary model file; check it before writing.
  config::parseModel(model, options.outPath);
  const std::vector<std::filesystem::path> inputs = calibrateInputs(options);
  detail::writeJsonFile(options.outPath, model, inputs);
  if (!options.reportPath.empty()) {
    detail::writeJsonFile(options.reportPath, reportJson(fit, problem->parameterInfo(), context),
                          inputs);
  }
  if (!options.predictOutPath.empty()) {
    writePredictions(options.predictOutPath, context.predictedAt, inputs);
  }
  out << '\n';
  writeSummary(out, fit, problem->parameterInfo(), context);
  out << "\nmodel written to " << options.outPath;
  if (!options.reportPath.empty()) out << ", report to " << options.reportPath;
  if (!options.predictOutPath.empty()) out << ", predictions to " << options.predictOutPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::calibration
