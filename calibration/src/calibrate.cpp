#include "volcomp/calibration/calibrate.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "fit_analysis.hpp"

namespace volcomp::calibration {

bool CalibrationSettings::isValid(std::string* error, Field* field) const {
  const auto invalid = [&](Field which, const char* expected) {
    if (error != nullptr) *error = expected;
    if (field != nullptr) *field = which;
    return false;
  };
  if (!(lossScaleMm > 0.0)) return invalid(Field::LossScale, "expected > 0");
  if (!(rankTolerance > 0.0 && rankTolerance < 1.0)) {
    return invalid(Field::RankTolerance, "expected a value in (0, 1)");
  }
  // Only Levenberg-Marquardt robustifies residual blocks; the linear method has one fixed
  // factorisation and no weights to change.
  if (method == MethodChoice::Linear && loss != RobustLoss::None) {
    return invalid(Field::Loss, "a robust loss needs the Levenberg-Marquardt method (or auto)");
  }
  if (maxIterations < 1) return invalid(Field::MaxIterations, "expected >= 1");
  if (!(identification.angleScaleMm > 0.0)) return invalid(Field::AngleScale, "expected > 0");
  if (folds == 1 || folds < 0) return invalid(Field::Folds, "expected k >= 2");
  return true;
}

void requireSomethingToIdentify(const config::ModelDocument& templateDocument) {
  if (templateDocument.identify.empty()) {
    throw config::ConfigError(templateDocument.file, "components",
                              "nothing to identify: mark components with {\"identify\": ...}");
  }
}

CalibrationProblem calibrationProblem(config::ModelDocument templateDocument,
                                      MeasurementSet measurements,
                                      const CalibrationSettings& settings) {
  std::string error;
  if (!settings.isValid(&error)) throw std::invalid_argument("calibration settings: " + error);
  requireSomethingToIdentify(templateDocument);
  CalibrationProblem result;
  result.document = std::move(templateDocument);
  result.measurements = std::move(measurements);
  result.problem =
      makeIdentificationProblem(result.document, result.measurements, settings.identification);
  const bool linear = settings.method == MethodChoice::Linear ||
                      (settings.method == MethodChoice::Auto && result.problem->nearlyLinear() &&
                       settings.loss == RobustLoss::None);
  result.method = linear ? Method::Linear : Method::LevenbergMarquardt;
  return result;
}

namespace {

SolveOptions solveOptions(const CalibrationProblem& problem, const CalibrationSettings& settings) {
  SolveOptions options;
  options.method = problem.method;
  options.loss = settings.loss;
  options.lossScale = settings.lossScaleMm;
  options.rankTolerance = settings.rankTolerance;
  options.maxIterations = settings.maxIterations;
  options.progress = settings.progress;
  return options;
}

}  // namespace

FitResult fitCalibration(const CalibrationProblem& problem, const CalibrationSettings& settings) {
  return solve(*problem.problem, problem.problem->startVector(), solveOptions(problem, settings));
}

bool identifiesTooFew(const FitStatistics& statistics) {
  return 2 * statistics.rank < statistics.parameterCount;
}

DataCoverage calibrationCoverage(const CalibrationProblem& problem) {
  return detail::coverageOf(problem.measurements, problem.document);
}

CalibrationAnalysis analyseCalibration(const CalibrationProblem& problem, const FitResult& fit,
                                       const CalibrationSettings& settings,
                                       const std::optional<MeasurementSet>& validation) {
  const detail::ProblemFactory factory = [&](const MeasurementSet& set) {
    return makeIdentificationProblem(problem.document, set, settings.identification);
  };
  CalibrationAnalysis analysis;
  analysis.coverage = calibrationCoverage(problem);
  std::vector<PointPrediction> measured =
      detail::measuredPoints(problem.measurements, problem.document);
  detail::predictPoints(*problem.problem, fit, measured);
  analysis.prediction = summarise(measured);
  analysis.curves = detail::sampleCurves(*problem.problem, fit);
  if (validation) {
    analysis.validation = detail::validateWith(factory, *validation, fit);
  } else if (settings.folds >= 2) {
    // The same solver as the fit itself, so that the folds' residuals are comparable with it.
    analysis.validation = detail::crossValidate(factory, problem.measurements, settings.folds,
                                                solveOptions(problem, settings));
  }
  return analysis;
}

void predictErrors(const CalibrationProblem& problem, const FitResult& fit,
                   std::vector<PointPrediction>& points) {
  detail::predictPoints(*problem.problem, fit, points);
}

config::CalibrationRecord calibrationRecord(const CalibrationProblem& problem, const FitResult& fit,
                                            const CalibrationAnalysis& analysis) {
  const FitStatistics& st = fit.statistics;
  config::CalibrationRecord record;
  record.points = static_cast<int>(problem.measurements.points.size());
  record.parameterCount = st.parameterCount;
  record.rank = st.rank;
  record.residualRmsBeforeMm = fit.before.rms;
  record.residualRmsAfterMm = fit.after.rms;
  if (analysis.validation) record.residualRmsValidationMm = analysis.validation->stats.rms;
  record.s0Mm = std::sqrt(st.varianceFactor);
  const std::vector<ParameterInfo>& info = problem.problem->parameterInfo();
  for (std::size_t j = 0; j < st.identifiable.size(); ++j) {
    if (!st.identifiable[j]) record.notIdentifiable.push_back(info[j].name);
  }
  record.toolsMm = analysis.coverage.toolsMm;
  return record;
}

nlohmann::json identifiedModel(const CalibrationProblem& problem, const FitResult& fit,
                               const config::CalibrationRecord& record) {
  nlohmann::json model = problem.problem->modelJson(fit.parameters);
  model["calibration"] = config::writeCalibrationRecord(record);
  return model;
}

}  // namespace volcomp::calibration
