#include "calibrate_verb.hpp"

#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <sstream>
#include <vector>

#include <CLI/CLI.hpp>

#include "calibration_files.hpp"
#include "planar2dof_verb.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/calibration/planar2dof_device.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {

CLI::App* addCalibrateVerb(CLI::App& app, CalibrateArguments& arguments) {
  CalibrateOptions& options = arguments.options;
  calibration::CalibrationSettings& settings = options.settings;
  CLI::App* verb = app.add_subcommand(
      "calibrate",
      "Identify model parameters from measurements. TEMPLATE is a model file whose components say "
      "how to identify them ({\"identify\": \"constant\"}, {\"identify\": {\"basis\": "
      "\"polynomial\", \"degree\": N}}, {\"identify\": {\"basis\": \"table\", \"positions\": "
      "[...]}}), or a planar 2-DOF device file (\"format\": \"volcomp-planar2dof/1\", readings "
      "a,b,gx,gy); MEASUREMENTS is a CSV with header x,y,z,ex,ey,ez [,tx,ty,tz] [,ea,eb,ec] "
      "[,weight] [,direction] (mm, rad; a unit suffix such as ex_um is allowed). Writes an "
      "ordinary model file (with a \"calibration\" block: provenance, measured tools) and prints "
      "the parameters with their standard deviations, residuals per axis, prediction "
      "uncertainty, identified curves and the combinations the data cannot separate.");
  verb->add_option("template", options.templatePath, "Calibration template (volcomp-model/1)")
      ->required();
  verb->add_option("measurements", options.measurementsPath, "Measurement CSV")->required();
  verb->add_option("--out", options.outPath, "Identified model file to write")->required();
  verb->add_option("--report", options.reportPath, "Also write the report as JSON");
  verb->add_option("--method", arguments.method,
                   "auto (linear for 3-axis models, Levenberg-Marquardt for D-H chains and "
                   "robust losses), linear or lm")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "linear", "lm"}));
  verb->add_option("--loss", arguments.loss, "Robust loss: none, huber or cauchy (needs lm)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "huber", "cauchy"}));
  verb->add_option("--loss-scale", settings.lossScaleMm,
                   "Residual size (mm) beyond which the robust loss down-weights")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_flag("--instrument-frame", settings.identification.instrumentFrame,
                 "Also fit the instrument's frame (3 rotations + 3 translations, nuisance)");
  verb->add_option("--rank-tol", settings.rankTolerance,
                   "Relative singular-value threshold of the rank decision (column-scaled)")
      ->capture_default_str()
      ->check(CLI::Range(1e-16, 0.5));
  verb->add_option("--angle-scale", settings.identification.angleScaleMm,
                   "Weight of measured angular errors: mm of residual per rad")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  verb->add_option("--max-iterations", settings.maxIterations, "Iteration limit")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  CLI::Option* validate = verb->add_option(
      "--validate", options.validatePath,
      "Held-out measurements (same CSV format): their residuals are reported beside the fit's");
  verb->add_option("--k-fold", settings.folds,
                   "Cross-validate: K fits, each predicting the points of one fold (K >= 2)")
      ->check(CLI::Range(2, 1000))
      ->excludes(validate);
  CLI::Option* predict = verb->add_option(
      "--predict", options.predictPath,
      "Points x,y,z [,tx,ty,tz] [,direction] at which to predict the error with its standard "
      "uncertainty");
  CLI::Option* predictOut = verb->add_option(
      "--predict-out", options.predictOutPath,
      "CSV written for --predict: x,y,z,tx,ty,tz,ex,ey,ez,ux,uy,uz,k,determined (mm; u standard "
      "uncertainty, k the coverage factor of U = k u)");
  predict->needs(predictOut);
  predictOut->needs(predict);
  verb->add_option("--angle-unit", arguments.angleUnit, "Angles on screen: urad or arcsec")
      ->capture_default_str()
      ->check(CLI::IsMember({"urad", "arcsec"}));
  verb->add_flag("--force", options.force,
                 "Write the model even when the data identify fewer than half of the parameters");
  verb->footer(
      "Exit status: 0 done (unidentifiable parameters are reported, not an error); 2 bad "
      "arguments, a bad template/CSV, or data that identify fewer than half of the parameters "
      "without --force (one line on stderr: file, line or key, expectation).");
  return verb;
}

namespace {

using calibration::CalibrationSettings;
using config::ConfigError;

void resolveMethod(const std::string& text, CalibrationSettings& settings) {
  if (text == "auto") {
    settings.method = calibration::MethodChoice::Auto;
  } else if (text == "linear") {
    settings.method = calibration::MethodChoice::Linear;
  } else if (text == "lm") {
    settings.method = calibration::MethodChoice::LevenbergMarquardt;
  } else {
    throw ConfigError(kCommandLine, "--method", "expected auto, linear or lm, got " + text);
  }
}

void resolveLoss(const std::string& text, CalibrationSettings& settings) {
  if (text == "none") {
    settings.loss = calibration::RobustLoss::None;
  } else if (text == "huber") {
    settings.loss = calibration::RobustLoss::Huber;
  } else if (text == "cauchy") {
    settings.loss = calibration::RobustLoss::Cauchy;
  } else {
    throw ConfigError(kCommandLine, "--loss", "expected none, huber or cauchy, got " + text);
  }
}

const char* optionOf(CalibrationSettings::Field field) {
  switch (field) {
    case CalibrationSettings::Field::Method:
      return "--method";
    case CalibrationSettings::Field::Loss:
      return "--loss";
    case CalibrationSettings::Field::LossScale:
      return "--loss-scale";
    case CalibrationSettings::Field::RankTolerance:
      return "--rank-tol";
    case CalibrationSettings::Field::MaxIterations:
      return "--max-iterations";
    case CalibrationSettings::Field::AngleScale:
      return "--angle-scale";
    case CalibrationSettings::Field::Folds:
      return "--k-fold";
  }
  return "";
}

// Every file the run reads: no output may replace one of them (volcomp::output).
std::vector<std::filesystem::path> calibrateInputs(const CalibrateOptions& options) {
  std::vector<std::filesystem::path> inputs{options.templatePath, options.measurementsPath};
  if (!options.validatePath.empty()) inputs.emplace_back(options.validatePath);
  if (!options.predictPath.empty()) inputs.emplace_back(options.predictPath);
  return inputs;
}

// The option checks of the run, before any file is read.
void checkOptions(const CalibrateOptions& options) {
  std::string problem;
  CalibrationSettings::Field field{};
  if (!options.settings.isValid(&problem, &field)) {
    throw ConfigError(kCommandLine, optionOf(field), problem);
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
  if (options.predictPath.empty() != options.predictOutPath.empty()) {
    throw ConfigError(kCommandLine, "--predict", "--predict and --predict-out go together");
  }
}

// Points to predict at: the shared CSV reader, positions with optional tool and direction.
std::vector<calibration::PointPrediction> readPredictionPoints(
    const std::string& path, const Eigen::Vector3d& templateTool) {
  std::ifstream input = config::CsvReader::open(path);
  config::CsvReader csv(input, path, config::positionsSchema());
  const int direction = csv.column("direction");
  std::vector<calibration::PointPrediction> points;
  while (csv.next()) {
    calibration::PointPrediction p;
    p.qMm = {csv.number("x"), csv.number("y"), csv.number("z")};
    p.toolMm = csv.has("tx") ? Eigen::Vector3d(csv.number("tx"), csv.number("ty"), csv.number("tz"))
                             : templateTool;
    if (direction >= 0) p.directions = csv.directions(direction);
    p.line = static_cast<int>(csv.line());
    points.push_back(p);
  }
  return points;
}

void writePredictions(const std::string& path,
                      const std::vector<calibration::PointPrediction>& points,
                      const std::vector<std::filesystem::path>& inputs) {
  std::ostringstream file;
  file.precision(17);
  file << "x,y,z,tx,ty,tz,ex,ey,ez,ux,uy,uz,k,determined\n";
  for (const calibration::PointPrediction& p : points) {
    for (const Eigen::Vector3d* v : {&p.qMm, &p.toolMm, &p.errorMm}) {
      file << v->x() + 0.0 << ',' << v->y() + 0.0 << ',' << v->z() + 0.0 << ',';
    }
    for (int axis = 0; axis < 3; ++axis) {
      // An undetermined prediction has no uncertainty to write: the field stays empty.
      if (p.determined) file << p.stdMm(axis);
      file << ',';
    }
    file << calibration::kCoverageFactor << ',' << (p.determined ? 1 : 0) << '\n';
  }
  output::writeOutputFile(path, file.str(), inputs);
}

}  // namespace

void resolveCalibrateArguments(CalibrateArguments& arguments) {
  resolveMethod(arguments.method, arguments.options.settings);
  resolveLoss(arguments.loss, arguments.options.settings);
  arguments.options.angleDisplay = angleDisplayFromText(arguments.angleUnit);
}

int runCalibrate(const CalibrateOptions& options, std::ostream& out) {
  checkOptions(options);
  CalibrationSettings settings = options.settings;
  settings.progress = [&out](const std::string& line) { out << "  " << line << std::endl; };
  const nlohmann::json templateJson = config::readJsonFile(options.templatePath);
  if (calibration::isPlanar2DofDocument(templateJson)) {
    return runPlanar2Dof(templateJson, options, out);
  }
  config::ParseOptions parseOptions;
  parseOptions.allowIdentify = true;
  config::ModelDocument document =
      config::parseModel(templateJson, options.templatePath, parseOptions);
  calibration::requireSomethingToIdentify(document);
  calibration::MeasurementSet measurements =
      calibration::readMeasurementsCsv(options.measurementsPath);
  out << "read " << measurements.points.size() << " points from " << options.measurementsPath
      << std::endl;
  const calibration::CalibrationProblem problem =
      calibration::calibrationProblem(std::move(document), std::move(measurements), settings);
  const calibration::IdentificationProblem& identification = *problem.problem;
  if (problem.underdetermined()) {
    out << "warning: " << identification.rowCount() << " equations for "
        << identification.parameterCount() << " parameters: some combinations cannot be identified"
        << std::endl;
  }
  const bool linear = problem.method == calibration::Method::Linear;
  out << "identifying " << identification.parameterCount() << " parameters ("
      << (linear ? "linear identification" : "Levenberg-Marquardt") << ")" << std::endl;

  const calibration::FitResult fit = calibration::fitCalibration(problem, settings);

  calibration::ReportContext context;
  context.templateFile = options.templatePath;
  context.measurementFile = options.measurementsPath;
  context.method = problem.method;
  context.loss = settings.loss;
  context.rankTolerance = settings.rankTolerance;
  context.volcompVersion = options.volcompVersion;
  context.date = utcNow();
  context.angleDisplay = options.angleDisplay;
  for (const calibration::Measurement& m : problem.measurements.points) {
    context.lines.push_back(m.line);
  }
  context.coverage = calibration::calibrationCoverage(problem);

  const calibration::FitStatistics& st = fit.statistics;
  if (calibration::identifiesTooFew(st) && !options.force) {
    out << '\n';
    calibration::writeMissingSummary(out, fit, identification.parameterInfo(), context);
    throw ConfigError(options.measurementsPath, "",
                      "the measurements identify " + std::to_string(st.rank) + " of " +
                          std::to_string(st.parameterCount) +
                          " independent parameters: far too few, nothing written (what is "
                          "missing is above; --force writes the model anyway)");
  }

  std::optional<calibration::MeasurementSet> validation;
  if (!options.validatePath.empty()) {
    validation = calibration::readMeasurementsCsv(options.validatePath);
  } else if (settings.folds >= 2) {
    out << "cross-validating: " << settings.folds << " fits, each without one fold of the points"
        << std::endl;
  }
  const calibration::CalibrationAnalysis analysis =
      calibration::analyseCalibration(problem, fit, settings, validation);
  context.prediction = analysis.prediction;
  context.curves = analysis.curves;
  context.validation = analysis.validation;
  if (!options.predictPath.empty()) {
    const auto* spec = std::get_if<model::MachineModelSpec>(&problem.document.spec);
    context.predictedAt = readPredictionPoints(
        options.predictPath, spec != nullptr ? spec->toolMm : Eigen::Vector3d::Zero());
    calibration::predictErrors(problem, fit, context.predictedAt);
  }

  config::CalibrationRecord record = calibration::calibrationRecord(problem, fit, analysis);
  record.volcompVersion = options.volcompVersion;
  record.date = context.date;
  record.templateFile = options.templatePath;
  record.measurementFiles = {options.measurementsPath};
  record.validationFile = options.validatePath;

  const nlohmann::json model = calibration::identifiedModel(problem, fit, record);
  // The output must load as an ordinary model file; check it before writing.
  config::parseModel(model, options.outPath);
  const std::vector<std::filesystem::path> inputs = calibrateInputs(options);
  writeJsonFile(options.outPath, model, inputs);
  if (!options.reportPath.empty()) {
    writeJsonFile(options.reportPath,
                  calibration::reportJson(fit, identification.parameterInfo(), context), inputs);
  }
  if (!options.predictOutPath.empty()) {
    writePredictions(options.predictOutPath, context.predictedAt, inputs);
  }
  out << '\n';
  calibration::writeSummary(out, fit, identification.parameterInfo(), context);
  out << "\nmodel written to " << options.outPath;
  if (!options.reportPath.empty()) out << ", report to " << options.reportPath;
  if (!options.predictOutPath.empty()) out << ", predictions to " << options.predictOutPath;
  out << std::endl;
  return 0;
}

}  // namespace volcomp::cli
