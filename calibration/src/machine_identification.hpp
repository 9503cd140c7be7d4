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
  int priorRowCount() const override;
  void priorResiduals(const double* p, double* r) const override;
  void priorJacobian(const double* p, double* jacobian) const override;
  double observationWeight(int i) const override;
  int statisticsRows() const override { return 3; }

  Eigen::VectorXd startVector() const override;
  nlohmann::json modelJson(const Eigen::VectorXd& p) const override;
  bool nearlyLinear() const override { return true; }

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
    model::MotionValues baseMotion{};
    double sqrtWeight = 1.0;
    double weight = 1.0;
  };

  static IdentifySpec parseIdentify(const nlohmann::json& block, const std::string& file,
                                    const std::string& path);
  static std::vector<double> startValues(const Component& component,
                                         const model::ErrorFunctionSpec& start,
                                         const std::string& file, const std::string& path);
  void evaluateBasis(const Component& component, double qMm, double* out) const;
  void motionValues(const double* p, int i, model::MotionValues& values) const;
  void predict(const double* p, int i, const model::MotionValues& values, double* out) const;

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
};

}  // namespace volcomp::calibration::detail
