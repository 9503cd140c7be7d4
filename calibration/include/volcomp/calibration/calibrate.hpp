#pragma once
/// Calibrating a template (a model file whose components say `{"identify": ...}`) from
/// measurements, in the steps a program strings together: the identification problem and the
/// method that fits it (calibrationProblem), the fit (fitCalibration), what a report states
/// beyond the fit (analyseCalibration: predictions with their uncertainty, identified curves,
/// held-out residuals), the record the identified model carries (calibrationRecord) and the
/// identified model document (identifiedModel).
///
/// Nothing here reads option text, prints or writes a file (tools/cli does). Numerical outcomes
/// are data in the results: parameters the data cannot identify (FitStatistics), data that
/// identify far too few (identifiesTooFew), a fit that did not converge (FitResult::converged).
/// Units: mm and rad internally; the model document is in the template's error units.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/calibration/report.hpp"
#include "volcomp/config/calibration_record.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {

/// Which solver fits the parameters.
enum class MethodChoice {
  /// Linear identification for templates linear in their parameters up to second-order terms
  /// (3-axis models) without a robust loss; Levenberg-Marquardt otherwise (D-H chains, robust
  /// losses).
  Auto,
  Linear,
  LevenbergMarquardt,
};

struct CalibrationSettings {
  MethodChoice method = MethodChoice::Auto;
  /// Robust loss (Levenberg-Marquardt only): residuals beyond lossScaleMm (mm) are down-weighted.
  RobustLoss loss = RobustLoss::None;
  double lossScaleMm = 0.01;
  /// Relative singular-value threshold of the rank decision (column-scaled Jacobian), in (0, 1).
  double rankTolerance = 1e-7;
  int maxIterations = 100;
  IdentificationOptions identification;
  /// k >= 2: k-fold cross-validation of the measurements (k more fits); 0: none.
  int folds = 0;
  /// Receives one line per solver iteration (the cross-validation fits' too); may be empty.
  std::function<void(const std::string&)> progress;

  /// The settings, to name the one that cannot be used.
  enum class Field { Method, Loss, LossScale, RankTolerance, MaxIterations, AngleScale, Folds };
  /// True when the settings can be used. Otherwise false, with *error saying what the value of
  /// *field must be (e.g. "expected > 0"); either pointer may be null.
  bool isValid(std::string* error, Field* field = nullptr) const;
};

/// A template's identification problem for a measurement set and the method that fits it.
struct CalibrationProblem {
  config::ModelDocument document;
  MeasurementSet measurements;
  std::unique_ptr<IdentificationProblem> problem;
  /// settings.method with Auto decided.
  Method method = Method::Linear;
  /// Fewer equations than parameters: some combinations stay unidentified whatever the values.
  bool underdetermined() const { return problem->rowCount() < problem->parameterCount(); }
};

/// Throws config::ConfigError at "components" when the template marks nothing to identify.
void requireSomethingToIdentify(const config::ModelDocument& templateDocument);

/// Builds the problem of a template parsed with config::ParseOptions::allowIdentify. Throws
/// config::ConfigError (file, key path, what was expected) when the template marks nothing to
/// identify ("components"), for bad identify blocks and for measurements that do not fit the
/// template; std::invalid_argument for settings that are not valid.
CalibrationProblem calibrationProblem(config::ModelDocument templateDocument,
                                      MeasurementSet measurements,
                                      const CalibrationSettings& settings);

/// Fits the parameters from the template's start values (progress through settings.progress).
FitResult fitCalibration(const CalibrationProblem& problem, const CalibrationSettings& settings);

/// The data identify fewer than half of the parameters (rank < n / 2): far too few for a model
/// worth writing.
bool identifiesTooFew(const FitStatistics& statistics);

/// What a report states beyond the fit's own residuals.
struct CalibrationAnalysis {
  DataCoverage coverage;
  /// Prediction uncertainty over the measured points.
  PredictionSummary prediction;
  std::vector<SampledCurve> curves;
  /// Residuals of held-out measurements (a validation set or settings.folds).
  std::optional<ValidationResult> validation;
};

/// What the data cover (spans against the travel, distinct tools), for messages about missing
/// data; available before the fit.
DataCoverage calibrationCoverage(const CalibrationProblem& problem);

/// Prediction uncertainty over the measured points, curves and held-out residuals of a fit.
/// `validation`: measurements held out of the fit (without them, settings.folds >= 2 runs a
/// k-fold cross-validation with the fit's solver).
CalibrationAnalysis analyseCalibration(const CalibrationProblem& problem, const FitResult& fit,
                                       const CalibrationSettings& settings,
                                       const std::optional<MeasurementSet>& validation);

/// Fills errorMm (mm, workpiece frame), stdMm (standard uncertainty per axis, mm; NaN where the
/// data do not determine it) and determined of each point from its qMm, toolMm and directions.
void predictErrors(const CalibrationProblem& problem, const FitResult& fit,
                   std::vector<PointPrediction>& points);

/// The record of the identified model without provenance (version, date and files are the
/// caller's): points, parameter count, rank, residual RMS (mm) before, after and held out, s0
/// (mm), the parameters not identifiable and the measured tools (mm).
config::CalibrationRecord calibrationRecord(const CalibrationProblem& problem, const FitResult& fit,
                                            const CalibrationAnalysis& analysis);

/// The identified model: the template with the fitted values (its error units) and `record` as
/// its "calibration" block.
nlohmann::json identifiedModel(const CalibrationProblem& problem, const FitResult& fit,
                               const config::CalibrationRecord& record);

}  // namespace volcomp::calibration
