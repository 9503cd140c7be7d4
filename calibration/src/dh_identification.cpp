// Identification of D-H deviations (see identification.hpp): a nonlinear problem solved with
// Levenberg-Marquardt; derivatives by central differences (few parameters, cheap chains), a
// parameter at a time over all points.

#include <cmath>
#include <numbers>
#include <regex>

#include "instrument_frame.hpp"
#include "machine_identification.hpp"
#include "volcomp/model/dh_chain.hpp"

namespace volcomp::calibration {
namespace detail {
namespace {

using config::ConfigError;

constexpr double kDegToRad = std::numbers::pi / 180.0;

enum class Field { Theta, D, A, Alpha, Rotation, Translation };

struct DeviationParameter {
  int link = 0;
  Field field = Field::D;
  int component = 0;  // for the triples
  double start = 0.0;
};

double& deviation(model::DhLinkSpec& link, Field field, int component) {
  switch (field) {
    case Field::Theta:
      return link.dThetaRad;
    case Field::D:
      return link.dDMm;
    case Field::A:
      return link.dAMm;
    case Field::Alpha:
      return link.dAlphaRad;
    case Field::Rotation:
      return link.dRotationRad[component];
    case Field::Translation:
      break;
  }
  return link.dTranslationMm[component];
}

class DhIdentification final : public IdentificationProblem {
 public:
  DhIdentification(const config::ModelDocument& document, const MeasurementSet& measurements,
                   const IdentificationOptions& options)
      : document_(document),
        template_(std::get<model::DhChainSpec>(document.spec)),
        options_(options),
        hasAngles_(measurements.hasAngles) {
    const std::string& file = document.file;
    const std::regex pattern(
        R"(chain\.links\[(\d+)\]\.(dtheta|dd|da|dalpha|drotation_deg|dtranslation))");
    for (const auto& [keyPath, block] : document.identify) {
      std::smatch match;
      if (!std::regex_match(keyPath, match, pattern)) {
        throw ConfigError(file, keyPath, "identify is supported for link deviations only");
      }
      if (!(block.is_string() && block.get<std::string>() == "constant") &&
          !(block.is_object() && block.size() == 1 && block.contains("basis") &&
            block.at("basis") == "constant")) {
        throw ConfigError(file, keyPath + ".identify",
                          "a D-H deviation is a constant: expected \"constant\"");
      }
      const int link = std::stoi(match[1].str());
      const std::string key = match[2].str();
      const std::string label = "links[" + std::to_string(link) + "]." + key;
      model::DhLinkSpec& spec = template_.links.at(static_cast<std::size_t>(link));
      // A structured binding cannot be captured by Clang 14's lambdas (C++20 allows it).
      const std::string& blockPath = keyPath;
      const auto add = [&](Field field, int component, const std::string& name, bool angle) {
        DeviationParameter parameter{link, field, component, deviation(spec, field, component)};
        parameters_.push_back(parameter);
        info_.push_back({name, blockPath, angle ? "deg" : "mm", angle ? 1.0 / kDegToRad : 1.0,
                         false, angle ? ParameterInfo::Kind::Angle : ParameterInfo::Kind::Length});
      };
      if (key == "dtheta") add(Field::Theta, 0, label, true);
      if (key == "dd") add(Field::D, 0, label, false);
      if (key == "da") add(Field::A, 0, label, false);
      if (key == "dalpha") add(Field::Alpha, 0, label, true);
      for (int c = 0; c < 3; ++c) {
        const std::string suffix = std::string("[") + "xyz"[c] + "]";
        if (key == "drotation_deg") add(Field::Rotation, c, label + suffix, true);
        if (key == "dtranslation") add(Field::Translation, c, label + suffix, false);
      }
    }
    if (options.instrumentFrame) {
      frameFirst_ = static_cast<int>(parameters_.size());
      appendFrameInfo(info_, "mm", 1.0, "deg", kDegToRad);
    }
    const model::DhChain chain(template_);
    const int joints = chain.jointCount();
    if (measurements.jointColumns == 0 && joints != 3) {
      throw ConfigError(measurements.file, "line 1",
                        "the chain has " + std::to_string(joints) +
                            " joints: give the joint values as columns q1..q" +
                            std::to_string(joints));
    }
    if (measurements.jointColumns != 0 && measurements.jointColumns != joints) {
      throw ConfigError(measurements.file, "line 1",
                        "expected " + std::to_string(joints) + " joint columns (q1..q" +
                            std::to_string(joints) + "), got " +
                            std::to_string(measurements.jointColumns));
    }
    if (measurements.hasTool) {
      throw ConfigError(measurements.file, "line 1",
                        "tool columns tx,ty,tz do not apply to a D-H chain (its last link is the "
                        "tool)");
    }
    // Joint types in chain order, to convert revolute values from degrees.
    std::vector<bool>& revolute = revolute_;
    for (const model::DhLinkSpec& link : template_.links) {
      if (link.joint == model::JointType::Revolute) revolute.push_back(true);
      if (link.joint == model::JointType::Prismatic) revolute.push_back(false);
    }
    for (const Measurement& m : measurements.points) {
      Point point;
      for (int j = 0; j < joints; ++j) {
        const double value =
            measurements.jointColumns > 0 ? m.joints[static_cast<std::size_t>(j)] : m.qMm[j];
        point.joints.push_back(revolute[static_cast<std::size_t>(j)] ? value * kDegToRad : value);
      }
      point.measuredMm = m.errorMm;
      point.measuredAngleRad = m.angularErrorRad;
      point.weight = m.weight;
      point.sqrtWeight = std::sqrt(m.weight);
      points_.push_back(std::move(point));
    }
  }

  int parameterCount() const override {
    return static_cast<int>(parameters_.size()) + (frameFirst_ >= 0 ? 6 : 0);
  }
  int observationCount() const override { return static_cast<int>(points_.size()); }
  int residualsPerObservation() const override { return hasAngles_ ? 6 : 3; }
  int statisticsRows() const override { return 3; }
  double observationWeight(int i) const override {
    return points_[static_cast<std::size_t>(i)].weight;
  }
  double parameterStep(int j, double pj) const override {
    const bool angle = info_[static_cast<std::size_t>(j)].unit == "deg";
    return (angle ? 1e-7 : 1e-5) * std::max(1.0, std::abs(pj));
  }

  void observationResiduals(const double* p, int i, double* r) const override {
    pointResiduals(model::DhChain(withDeviations(p)), p, i, r);
  }

  // The chain is built once per parameter vector rather than once per point: residuals for all
  // points, and the central differences a parameter at a time over all points (the same steps
  // and quotients as observationJacobian's, so the same numbers).
  void residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const override {
    const model::DhChain chain(withDeviations(p.data()));
    const int k = residualsPerObservation();
    r.resize(rowCount());
    for (int i = 0; i < observationCount(); ++i)
      pointResiduals(chain, p.data(), i, r.data() + i * k);
  }

  void jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const override {
    const int n = parameterCount();
    jacobian.resize(rowCount(), n);
    Eigen::VectorXd shifted = p, plus, minus;
    for (int j = 0; j < n; ++j) {
      const double h = parameterStep(j, p[j]);
      shifted[j] = p[j] + h;
      residuals(shifted, plus);
      shifted[j] = p[j] - h;
      residuals(shifted, minus);
      shifted[j] = p[j];
      jacobian.col(j) = (plus - minus) / (2.0 * h);
    }
  }

  Eigen::VectorXd startVector() const override {
    Eigen::VectorXd p = Eigen::VectorXd::Zero(parameterCount());
    for (std::size_t j = 0; j < parameters_.size(); ++j) {
      p(static_cast<Eigen::Index>(j)) = parameters_[j].start;
    }
    return p;
  }

  nlohmann::json modelJson(const Eigen::VectorXd& p) const override {
    return config::writeModel(withDeviations(p.data()));
  }
  bool nearlyLinear() const override { return false; }

 protected:
  Eigen::Vector3d predictError(const Eigen::VectorXd& p, const PredictionPoint& at) const override {
    const model::DhChain chain(withDeviations(p.data()));
    std::vector<double> joints;
    for (std::size_t j = 0; j < revolute_.size(); ++j) {
      const double value = at.joints.empty() ? at.qMm[static_cast<Eigen::Index>(j)] : at.joints[j];
      joints.push_back(revolute_[j] ? value * kDegToRad : value);
    }
    return chain.evaluate(joints.data()).errorMm;
  }

 private:
  struct Point {
    std::vector<double> joints;
    Eigen::Vector3d measuredMm, measuredAngleRad;
    double weight = 1.0;
    double sqrtWeight = 1.0;
  };

  void pointResiduals(const model::DhChain& chain, const double* p, int i, double* r) const {
    const Point& point = points_[static_cast<std::size_t>(i)];
    const model::DhResult result = chain.evaluate(point.joints.data());
    const Eigen::Vector3d nominal = result.tNominal.block<3, 1>(0, 3);
    const double* frame = frameFirst_ >= 0 ? p + frameFirst_ : nullptr;
    const Eigen::Vector3d position = predictedPositionError(frame, nominal, result.errorMm);
    for (int t = 0; t < 3; ++t) r[t] = (position[t] - point.measuredMm[t]) * point.sqrtWeight;
    if (hasAngles_) {
      const Eigen::Vector3d angle = predictedAngularError(frame, result.angularErrorRad);
      for (int t = 0; t < 3; ++t) {
        r[3 + t] =
            (angle[t] - point.measuredAngleRad[t]) * point.sqrtWeight * options_.angleScaleMm;
      }
    }
  }

  model::DhChainSpec withDeviations(const double* p) const {
    model::DhChainSpec spec = template_;
    for (std::size_t j = 0; j < parameters_.size(); ++j) {
      const DeviationParameter& parameter = parameters_[j];
      deviation(spec.links[static_cast<std::size_t>(parameter.link)], parameter.field,
                parameter.component) = p[j];
    }
    return spec;
  }

  config::ModelDocument document_;
  model::DhChainSpec template_;
  IdentificationOptions options_;
  bool hasAngles_ = false;
  std::vector<DeviationParameter> parameters_;
  std::vector<bool> revolute_;
  int frameFirst_ = -1;
  std::vector<Point> points_;
};

}  // namespace
}  // namespace detail

std::unique_ptr<IdentificationProblem> makeIdentificationProblem(
    const config::ModelDocument& document, const MeasurementSet& measurements,
    const IdentificationOptions& options) {
  if (std::holds_alternative<model::DhChainSpec>(document.spec)) {
    return std::make_unique<detail::DhIdentification>(document, measurements, options);
  }
  return std::make_unique<detail::MachineIdentification>(document, measurements, options);
}

}  // namespace volcomp::calibration
