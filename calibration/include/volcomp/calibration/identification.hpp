#pragma once
/// Identification problems built from a calibration template (a model file whose components say
/// `{"identify": ...}`) and measurements.
///
/// 3-axis models: an identified motion component K is replaced by a linear combination of basis
/// functions of its axis position (clamped to the travel): "constant" (1), "polynomial" of degree
/// N (1, q, ..., q^N; with "zero_at": z the terms (q - z)^1..(q - z)^N, so the function is 0 at
/// z; "min_degree": M starts at the power M, e.g. 2 for a straightness whose slope is left to the
/// squareness), "table" (the node values of a linear/quadratic/cubic table at given positions,
/// optional "smoothness" w adding prior rows sqrt(w) * (v[j-1] - 2 v[j] + v[j+1]), internal units).
/// Identified location errors (EA0K, ...) are constants. Non-identified components keep their
/// template values. D-H chains: identified deviations (dtheta, dd, da, dalpha, drotation_deg,
/// dtranslation) are constants.
///
/// Residuals per point: predicted - measured error (mm), with the optional instrument frame:
/// the instrument measures the actual point in its own frame I, p_I = R(w) p + t with
/// R(w) = Rz(w_z) Ry(w_y) Rx(w_x), so the predicted error is R(w) (p0 + E) + t - p0 (p0 the
/// nominal point). Measured angular errors add 3 rows: rotation vector of R(w) exp(Theta) minus
/// the measured one, times angleScaleMm (mm per rad) so that they weigh like lengths.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "volcomp/calibration/least_squares.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/types.hpp"

namespace volcomp::calibration {

struct ParameterInfo {
  /// Report name, e.g. "EXX c1", "EC0Y", "links[1].dd", "frame rz".
  std::string name;
  /// Template key path it comes from, e.g. "components.EXX" ("instrument_frame" for nuisance).
  std::string keyPath;
  /// Unit of the displayed value, e.g. "um", "urad", "um/mm^2", "deg".
  std::string unit;
  /// Displayed value = internal value (mm, rad) * toDisplay.
  double toDisplay = 1.0;
  /// Nuisance parameters (instrument frame) are fitted but not written to the model.
  bool nuisance = false;
  /// What the internal value is, for the screen's units (um and urad or arcsec): a length (mm)
  /// or an angle (rad) per mm^perMmPower (polynomial coefficients); Other is shown in `unit`.
  enum class Kind { Length, Angle, Other };
  Kind kind = Kind::Other;
  int perMmPower = 0;
};

/// A point at which to predict the machine's error with the identified parameters.
struct PredictionPoint {
  Eigen::Vector3d qMm = Eigen::Vector3d::Zero();
  /// Tool offset (mm); the template's when absent.
  std::optional<Eigen::Vector3d> toolMm;
  model::Directions directions{};
  /// D-H chains: joint values (mm, revolute deg); empty: x, y, z for 3-joint chains.
  std::vector<double> joints;
};

/// Which of a component's curves a Curve is.
enum class CurveDirection {
  Both,      ///< the one curve of a component that is not a bidirectional table
  Positive,  ///< a bidirectional table's curve for motion in + ("values")
  Negative,  ///< a bidirectional table's curve for motion in - ("values_negative")
  Reversal,  ///< the difference negative - positive of a bidirectional table
};

/// As reports write it: "" (Both), "+", "-", "reversal".
constexpr const char* curveDirectionName(CurveDirection direction) noexcept {
  switch (direction) {
    case CurveDirection::Positive:
      return "+";
    case CurveDirection::Negative:
      return "-";
    case CurveDirection::Reversal:
      return "reversal";
    case CurveDirection::Both:
      break;
  }
  return "";
}

/// An identified error function of one component sampled at a few positions: value = g . p and
/// its uncertainty through the fit's covariance (predictionUncertainty with g).
struct Curve {
  std::string component;  ///< e.g. "EXX"
  CurveDirection direction = CurveDirection::Both;
  std::string unit;        ///< display unit (the template's error units)
  double toDisplay = 1.0;  ///< internal value * toDisplay = displayed value
  bool angle = false;      ///< an angular component (rad internally)
  std::vector<double> positionsMm;
  /// Per position: d(value)/dp (internal units), dense over the parameters.
  std::vector<Eigen::RowVectorXd> gradients;
};

struct IdentificationOptions {
  /// Fit the instrument frame (3 rotations + 3 translations) as nuisance parameters.
  bool instrumentFrame = false;
  /// Weight of angular rows: mm of residual per rad of angular error.
  double angleScaleMm = 1000.0;
};

class IdentificationProblem : public ResidualProblem {
 public:
  const std::vector<ParameterInfo>& parameterInfo() const noexcept { return info_; }
  std::string parameterName(int j) const override {
    return info_[static_cast<std::size_t>(j)].name;
  }
  /// Start values (from the template's "start" values, 0 otherwise).
  virtual Eigen::VectorXd startVector() const = 0;
  /// The identified model as a volcomp-model/1 document (template with identified values).
  virtual nlohmann::json modelJson(const Eigen::VectorXd& p) const = 0;
  /// True for models linear in their parameters up to second-order terms (3-axis components),
  /// where the linear method is the default.
  virtual bool nearlyLinear() const = 0;
  /// The machine's predicted volumetric error at `at` (mm, workpiece frame; the instrument frame
  /// does not apply) and its 3 x n sensitivity to the parameters (internal units). The default
  /// uses central differences of predictError().
  virtual void prediction(const Eigen::VectorXd& p, const PredictionPoint& at,
                          Eigen::Vector3d& errorMm, Eigen::Ref<Eigen::MatrixXd> jacobian) const;
  /// The identified error functions sampled at their nodes (tables) or at 5 positions over the
  /// travel (polynomials); empty where the problem has no such functions (D-H chains).
  virtual std::vector<Curve> curves() const { return {}; }

 protected:
  /// The machine's predicted error at `at` (used by the default prediction()).
  virtual Eigen::Vector3d predictError(const Eigen::VectorXd& p, const PredictionPoint& at) const;
  std::vector<ParameterInfo> info_;
};

/// Builds the problem for a template parsed with ParseOptions::allowIdentify. Throws
/// config::ConfigError (file, key path, what was expected) for bad identify blocks and for
/// measurements that do not fit the template (e.g. joint columns for a 3-axis model).
std::unique_ptr<IdentificationProblem> makeIdentificationProblem(
    const config::ModelDocument& document, const MeasurementSet& measurements,
    const IdentificationOptions& options = {});

}  // namespace volcomp::calibration
