#pragma once
/// Calibration report: JSON (machine-readable, full precision, the template's error units) and a
/// readable summary (um and urad or arcsec, 3-4 significant digits). The JSON structure is
/// documented field by field in docs/calibration.md ("Report JSON").

#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

/// Screen unit for angles.
enum class AngleDisplay { Microradian, Arcsecond };

/// Coverage factor of expanded uncertainties (U = k sigma, about 95 % for a normal distribution).
inline constexpr double kCoverageFactor = 2.0;

/// The propagated uncertainty of the predicted error at one point.
struct PointPrediction {
  Eigen::Vector3d qMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d toolMm = Eigen::Vector3d::Zero();
  model::Directions directions{};
  int line = 0;  ///< line in the file it came from (0 if none)
  Eigen::Vector3d errorMm = Eigen::Vector3d::Zero();
  /// Standard uncertainty per axis (mm); NaN where the data do not determine the prediction.
  Eigen::Vector3d stdMm = Eigen::Vector3d::Zero();
  bool determined = true;
};

/// Prediction uncertainty over a set of points (e.g. the measured ones).
struct PredictionSummary {
  int points = 0;
  int undetermined = 0;
  /// Over determined points: RMS and max of |sigma| = sqrt(sx^2 + sy^2 + sz^2), and the max per
  /// axis (mm).
  double rmsStdMm = 0.0;
  double maxStdMm = 0.0;
  int maxIndex = -1;
  Eigen::Vector3d maxAxisStdMm = Eigen::Vector3d::Zero();
};
PredictionSummary summarise(const std::vector<PointPrediction>& predictions);

/// An identified curve with its values and standard deviations (NaN where undetermined), in
/// internal units.
struct SampledCurve {
  Curve curve;
  std::vector<double> values;
  std::vector<double> std;
  /// Sigma of value(position k) - value(first position): where the data fix a curve's shape
  /// but not its constant (shared with another component), the shape still has a sigma.
  std::vector<double> relativeStd;
  /// The mean over the positions and its sigma (used for the reversal of bidirectional tables).
  double mean = 0.0;
  double meanStd = 0.0;
};

/// Where held-out points come from: a file of their own, or the folds of a k-fold
/// cross-validation of the measurements.
enum class ValidationKind { File, KFold };
/// The report's names: "file", "k-fold".
const char* validationKindName(ValidationKind kind) noexcept;

/// Residuals of points held out of the fit.
struct ValidationResult {
  ValidationKind kind = ValidationKind::File;
  std::string file;  ///< the validation file (kind File)
  int folds = 0;     ///< k (kind KFold)
  ResidualStats stats;
  std::vector<int> lines;  ///< line of each held-out point, in the order of stats' indices
  std::vector<double> foldRmsMm;
  std::vector<int> foldRank;
};

/// What the measurements cover, for messages about missing data.
struct DataCoverage {
  int points = 0;
  std::array<std::array<double, 2>, 3> spanMm{};  ///< min, max of x, y, z
  std::array<std::optional<std::array<double, 2>>, 3> travelMm{};
  std::vector<Eigen::Vector3d> toolsMm;  ///< distinct tool offsets
};

/// What was calibrated: a machine (a model template) or Hanak, Zirn and Ruoff's planar device.
enum class ReportKind { Machine, Planar2Dof };
/// The report's names: "machine", "planar2dof".
const char* reportKindName(ReportKind kind) noexcept;
/// The report's names of the solver and the loss: "linear", "levenberg-marquardt"; "none",
/// "huber", "cauchy".
const char* methodName(Method method) noexcept;
const char* lossName(RobustLoss loss) noexcept;

struct ReportContext {
  std::string templateFile;
  std::string measurementFile;
  Method method = Method::Linear;
  RobustLoss loss = RobustLoss::None;
  double rankTolerance = 0.0;
  /// Line numbers of the measurement rows (for "worst point" messages); may be empty.
  std::vector<int> lines;
  std::string volcompVersion;
  std::string date;  ///< ISO 8601 UTC
  AngleDisplay angleDisplay = AngleDisplay::Microradian;
  ReportKind kind = ReportKind::Machine;
  std::optional<DataCoverage> coverage;
  std::optional<PredictionSummary> prediction;
  std::vector<PointPrediction> predictedAt;  ///< --predict points (JSON only)
  std::vector<SampledCurve> curves;
  std::optional<ValidationResult> validation;
};

/// How a value of a parameter is shown: unit name and factor from internal units.
struct DisplayUnit {
  std::string unit;
  double factor = 1.0;
};
/// The template's units (as in the JSON report): ParameterInfo::unit, ::toDisplay.
DisplayUnit templateUnit(const ParameterInfo& info);
/// The screen's units: um (per mm^k), urad or arcsec (per mm^k); Other keeps the template's.
DisplayUnit screenUnit(const ParameterInfo& info, AngleDisplay angles);
DisplayUnit screenUnit(bool angle, AngleDisplay angles);

/// A combination in physical units: one unit of the pivot (in `units` of it) together with the
/// other parameters' changes, e.g. "1 urad of EC0Y with -1 urad of ECX[0] and +0.003 urad of
/// EAY[0]", lever arms where an angle goes with a length ("-0.1 um of EXX c0 (arm 100 mm)"), and
/// how much the measured residuals change for that step.
std::string physicalDescription(const Combination& combination,
                                const std::vector<ParameterInfo>& info, bool screen,
                                AngleDisplay angles);

/// {"format": "volcomp-calibration-report/1", ...}; see docs/calibration.md.
nlohmann::json reportJson(const FitResult& fit, const std::vector<ParameterInfo>& info,
                          const ReportContext& context);

/// The readable summary (parameters with start, value and sigma, residuals before/after/held
/// out per axis, rank and conditioning, prediction uncertainty, identified curves, strongest
/// correlations, and what the data cannot separate, in words).
void writeSummary(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info,
                  const ReportContext& context);

/// What the data miss, in a few lines instead of one per combination: per component how many of
/// its parameters are not identifiable, and what the measurements cover (spans against the
/// travel, tools).
void writeMissingSummary(std::ostream& out, const FitResult& fit,
                         const std::vector<ParameterInfo>& info, const ReportContext& context);

/// Text with `digits` significant digits ("-" for NaN).
std::string significant(double value, int digits);

}  // namespace volcomp::calibration
