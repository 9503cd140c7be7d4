#include "volcomp/calibration/planar2dof.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace volcomp::calibration {

std::string planar2DofName(int j) {
  static const std::array<const char*, kPlanar2DofParameterCount> names{
      "eLa", "eLb", "ea", "eha", "eb", "ehb", "phi", "exK", "eyK"};
  return names.at(static_cast<std::size_t>(j));
}

Eigen::Vector2d planar2DofForward(const Planar2DofGeometry& geometry, const Planar2DofParameters& u,
                                  double aMm, double bMm) noexcept {
  const Eigen::Vector2d footA(aMm + u[ea], u[eha]);
  const Eigen::Vector2d footB(bMm + u[eb], u[ehb]);
  const double legA = geometry.legAMm + u[eLa];
  const double legB = geometry.legBMm + u[eLb];
  const Eigen::Vector2d between = footB - footA;
  const double distance = between.norm();
  // Distance from A along AB to the foot of the TCP's perpendicular, then the height above AB.
  const double along = (legA * legA - legB * legB + distance * distance) / (2.0 * distance);
  const double heightSquared = legA * legA - along * along;
  if (!(heightSquared >= 0.0) || !(distance > 0.0)) {
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  const Eigen::Vector2d unit = between / distance;
  const Eigen::Vector2d normal(-unit.y(), unit.x());
  return footA + along * unit + std::sqrt(heightSquared) * normal;
}

Eigen::Vector2d planar2DofInverse(const Planar2DofGeometry& geometry, const Planar2DofParameters& u,
                                  const Eigen::Vector2d& tcpMm) noexcept {
  // Each foot lies on its own guide line y = eh at leg length from the TCP: A left, B right.
  const double legA = geometry.legAMm + u[eLa];
  const double legB = geometry.legBMm + u[eLb];
  const double dyA = tcpMm.y() - u[eha];
  const double dyB = tcpMm.y() - u[ehb];
  const double a = tcpMm.x() - std::sqrt(legA * legA - dyA * dyA) - u[ea];
  const double b = tcpMm.x() + std::sqrt(legB * legB - dyB * dyB) - u[eb];
  return {a, b};
}

Planar2DofProblem::Planar2DofProblem(Planar2DofGeometry geometry,
                                     std::vector<Planar2DofSample> samples, int referenceIndex,
                                     std::array<bool, kPlanar2DofParameterCount> free,
                                     Planar2DofParameters values)
    : geometry_(geometry),
      samples_(std::move(samples)),
      reference_(referenceIndex),
      values_(values) {
  if (reference_ < 0 || reference_ >= static_cast<int>(samples_.size())) {
    throw std::invalid_argument("planar 2-DOF calibration: reference index out of range");
  }
  for (int j = 0; j < kPlanar2DofParameterCount; ++j) {
    if (free[static_cast<std::size_t>(j)]) freeIndex_.push_back(j);
  }
}

Planar2DofParameters Planar2DofProblem::full(const double* p) const {
  Planar2DofParameters u = values_;
  for (std::size_t j = 0; j < freeIndex_.size(); ++j) {
    u[static_cast<std::size_t>(freeIndex_[j])] = p[j];
  }
  return u;
}

Eigen::VectorXd Planar2DofProblem::freeVector(const Planar2DofParameters& u) const {
  Eigen::VectorXd p(static_cast<Eigen::Index>(freeIndex_.size()));
  for (std::size_t j = 0; j < freeIndex_.size(); ++j) {
    p(static_cast<Eigen::Index>(j)) = u[static_cast<std::size_t>(freeIndex_[j])];
  }
  return p;
}

void Planar2DofProblem::observationResiduals(const double* p, int i, double* r) const {
  const Planar2DofParameters u = full(p);
  const Planar2DofSample& sample = samples_[static_cast<std::size_t>(i)];
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d relative = planar2DofForward(geometry_, u, sample.aMm, sample.bMm) -
                                   planar2DofForward(geometry_, u, reference.aMm, reference.bMm);
  const double c = std::cos(u[phi]), s = std::sin(u[phi]);
  const Eigen::Vector2d rotated(c * relative.x() + s * relative.y(),
                                -s * relative.x() + c * relative.y());
  const Eigen::Vector2d difference =
      rotated - (sample.lgpMm - reference.lgpMm) + Eigen::Vector2d(u[exK], u[eyK]);
  r[0] = difference.x();
  r[1] = difference.y();
}

std::string Planar2DofProblem::parameterName(int j) const {
  return planar2DofName(freeIndex_[static_cast<std::size_t>(j)]);
}

double Planar2DofProblem::parameterStep(int j, double pj) const {
  // Lengths in mm around ~250 mm arms, phi in rad: steps well above rounding, far below curvature.
  const bool angle = freeIndex_[static_cast<std::size_t>(j)] == phi;
  return (angle ? 1e-7 : 1e-5) * std::max(1.0, std::abs(pj));
}

}  // namespace volcomp::calibration
