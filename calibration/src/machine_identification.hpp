#pragma once
// Internal: the 3-axis identification problem (public entry point: identification.hpp).

#include <array>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::calibration::detail {

/// Central-difference steps of the numeric derivatives with respect to a translation (mm) and a
/// rotation (rad) parameter: small against any error, large against rounding of the model.
inline constexpr double kTranslationStepMm = 1e-3;
inline constexpr double kRotationStepRad = 1e-6;

struct IdentifySpec {
  enum class Basis { Constant, Polynomial, Table };
  Basis basis = Basis::Constant;
  int degree = 0;
  /// Lowest power of the polynomial basis: 0, or 1 with zero_at, unless "min_degree" says.
  int minDegree = 0;
  bool hasZeroAt = false;
  double zeroAtMm = 0.0;
  std::vector<double> positions;
  model::Interpolation interpolation = model::Interpolation::Linear;
  double smoothness = 0.0;
  /// Tables only: identify `values` (positive direction) and `values_negative` in one fit.
  bool bidirectional = false;
};

class MachineIdentification final : public IdentificationProblem {
 public:
  MachineIdentification(const config::ModelDocument& document, const MeasurementSet& measurements,
                        const IdentificationOptions& options);

  int parameterCount() const override { return parameterCount_; }
  int observationCount() const override { return static_cast<int>(points_.size()); }
  int residualsPerObservation() const override;
  void observationResiduals(const double* p, int i, double* r) const override;
  void observationJacobian(const double* p, int i, double* jacobian) const override;
  /// The whole sensitivity matrix on the model's batch path (machine_jacobian.cpp).
  void jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const override;
  int priorRowCount() const override;
  void priorResiduals(const double* p, double* r) const override;
  void priorJacobian(const double* p, double* jacobian) const override;
  double observationWeight(int i) const override;
  int statisticsRows() const override { return 3; }

  Eigen::VectorXd startVector() const override;
  nlohmann::json modelJson(const Eigen::VectorXd& p) const override;
  bool nearlyLinear() const override { return true; }
  void prediction(const Eigen::VectorXd& p, const PredictionPoint& at, Eigen::Vector3d& errorMm,
                  Eigen::Ref<Eigen::MatrixXd> jacobian) const override;
  std::vector<Curve> curves() const override;

  model::MachineModelSpec identifiedSpec(const Eigen::VectorXd& p) const;

 private:
  struct Component {
    int motion = 0;
    int axis = 0;
    IdentifySpec spec;
    int first = 0;
    int count = 0;
    std::vector<model::ErrorFunction> nodeBasis;
    std::vector<double> start;
  };
  struct LocationParameter {
    int index = 0;
    int parameter = 0;
    double start = 0.0;
  };
  struct Point {
    Eigen::Vector3d qMm, toolMm, nominalMm, measuredMm, measuredAngleRad;
    model::Directions directions{};
    model::MotionValues baseMotion{};
    double sqrtWeight = 1.0;
    double weight = 1.0;
  };

  static IdentifySpec parseIdentify(const nlohmann::json& block, const std::string& file,
                                    const std::string& path);
  static std::vector<double> startValues(const Component& component,
                                         const model::ErrorFunctionSpec& start,
                                         const std::string& file, const std::string& path);
  /// Basis values of a component at its axis position (clamped to the travel) approached in
  /// `direction` (bidirectional tables: the positive or the negative half, or half of each).
  void evaluateBasis(const Component& component, double qMm, model::Direction direction,
                     double* out) const;
  Point makePoint(const Eigen::Vector3d& qMm, const Eigen::Vector3d& toolMm,
                  const model::Directions& directions, double* basisRow) const;
  void motionValues(const double* p, const Point& point, const double* basis,
                    model::MotionValues& values) const;
  /// Predicted rows (3 position rows, then 3 angle rows when `rows` is 6), seen through the
  /// instrument frame when `frame` is not null.
  void predict(const double* frame, const Point& point, const model::MotionValues& values, int rows,
               double* out) const;
  /// d(direction of the axis of `location`, signed as the axis moves)/d(its angle), rad^-1, at
  /// the parameters `p` (the axis's other location angles from `p` where identified, else from
  /// the template): a central difference of the ZYX rotation's column.
  Eigen::Vector3d locationDirectionDerivative(const LocationParameter& location,
                                              const double* p) const;
  /// Unweighted rows x n Jacobian of predict() at point; with `instrument` the frame parameters
  /// take part, otherwise their columns are zero (the machine's own error).
  void jacobianAt(const double* p, const Point& point, const double* basis, int rows,
                  bool instrument, double* jacobian) const;

  config::ModelDocument document_;
  model::MachineModelSpec template_;
  IdentificationOptions options_;
  bool hasAngles_ = false;
  std::vector<Component> components_;
  std::vector<LocationParameter> locations_;
  int frameFirst_ = -1;
  int parameterCount_ = 0;
  int priorRows_ = 0;
  std::optional<model::MachineModel> model_;
  // Evaluation scratch space; problems are evaluated from one thread.
  std::unique_ptr<model::Workspace> workspace_;
  std::vector<int> needed_;
  std::array<double, 3> axisSign_{};
  std::array<Eigen::Vector3d, 3> baseDirection_;
  std::vector<Point> points_;
  std::vector<double> basis_;
  std::size_t basisWidth_ = 0;
  /// The points grouped by tool offset, for evaluations many points at a time.
  struct ToolGroup {
    Eigen::Vector3d toolMm;
    std::vector<int> points;
    std::vector<Eigen::Vector3d> qMm;
    std::vector<model::Directions> directions;
  };
  std::vector<ToolGroup> toolGroups_;
};

}  // namespace volcomp::calibration::detail
