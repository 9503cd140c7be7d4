// Defaults of IdentificationProblem's prediction interface (see identification.hpp).

#include "volcomp/calibration/identification.hpp"

#include <limits>

namespace volcomp::calibration {

Eigen::Vector3d IdentificationProblem::predictError(const Eigen::VectorXd&,
                                                    const PredictionPoint&) const {
  return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
}

void IdentificationProblem::prediction(const Eigen::VectorXd& p, const PredictionPoint& at,
                                       Eigen::Vector3d& errorMm,
                                       Eigen::Ref<Eigen::MatrixXd> jacobian) const {
  errorMm = predictError(p, at);
  Eigen::VectorXd shifted = p;
  for (Eigen::Index j = 0; j < p.size(); ++j) {
    const double h = parameterStep(static_cast<int>(j), p(j));
    shifted(j) = p(j) + h;
    const Eigen::Vector3d plus = predictError(shifted, at);
    shifted(j) = p(j) - h;
    const Eigen::Vector3d minus = predictError(shifted, at);
    shifted(j) = p(j);
    jacobian.col(j) = (plus - minus) / (2.0 * h);
  }
}

}  // namespace volcomp::calibration
