#include "volcomp/calibration/planar2dof.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <Eigen/LU>

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

namespace {

// R(phi) = [cos sin; -sin cos]: device frame to LGP frame (planar2dof.hpp).
Eigen::Matrix2d lgpRotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix2d rotation;
  rotation << c, s, -s, c;
  return rotation;
}

}  // namespace

Eigen::Vector2d Planar2DofProblem::residualsAt(const Planar2DofParameters& u, int i,
                                               const Eigen::Vector2d& tcpReference,
                                               const Eigen::Matrix2d& rotation) const {
  const Planar2DofSample& sample = samples_[static_cast<std::size_t>(i)];
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d relative =
      planar2DofForward(geometry_, u, sample.aMm, sample.bMm) - tcpReference;
  return rotation * relative - (sample.lgpMm - reference.lgpMm) + Eigen::Vector2d(u[exK], u[eyK]);
}

void Planar2DofProblem::observationResiduals(const double* p, int i, double* r) const {
  const Planar2DofParameters u = full(p);
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d difference = residualsAt(
      u, i, planar2DofForward(geometry_, u, reference.aMm, reference.bMm), lgpRotation(u[phi]));
  r[0] = difference.x();
  r[1] = difference.y();
}

void Planar2DofProblem::residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
  const Planar2DofParameters u = full(p.data());
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d tcpReference =
      planar2DofForward(geometry_, u, reference.aMm, reference.bMm);
  const Eigen::Matrix2d rotation = lgpRotation(u[phi]);
  r.resize(rowCount());
  for (int i = 0; i < observationCount(); ++i) {
    r.segment<2>(2 * i) = residualsAt(u, i, tcpReference, rotation);
  }
}

namespace {

// The TCP and its derivatives with respect to the nine parameters (2 x 9), from the implicit
// circle equations (planar2dof.hpp): cheaper and exact where central differences of the
// forward kinematics cost 4 evaluations per free parameter and carry their truncation error.
Eigen::Vector2d forwardWithDerivative(const Planar2DofGeometry& geometry,
                                      const Planar2DofParameters& u, double aMm, double bMm,
                                      Planar2DofProblem::TcpDerivative& derivative) {
  const Eigen::Vector2d tcp = planar2DofForward(geometry, u, aMm, bMm);
  const Eigen::Vector2d fromA = tcp - Eigen::Vector2d(aMm + u[ea], u[eha]);
  const Eigen::Vector2d fromB = tcp - Eigen::Vector2d(bMm + u[eb], u[ehb]);
  // Rows (T - A)^T and (T - B)^T; singular only when the legs are collinear (height 0), where
  // the forward kinematics has no derivative either: NaN then, like the position.
  Eigen::Matrix2d rows;
  rows << fromA.x(), fromA.y(), fromB.x(), fromB.y();
  const Eigen::Matrix2d inverse = rows.inverse();
  const Eigen::Vector2d alongA = inverse.col(0), alongB = inverse.col(1);
  derivative.setZero();
  derivative.col(eLa) = (geometry.legAMm + u[eLa]) * alongA;
  derivative.col(ea) = fromA.x() * alongA;
  derivative.col(eha) = fromA.y() * alongA;
  derivative.col(eLb) = (geometry.legBMm + u[eLb]) * alongB;
  derivative.col(eb) = fromB.x() * alongB;
  derivative.col(ehb) = fromB.y() * alongB;
  return tcp;
}

}  // namespace

void Planar2DofProblem::observationJacobian(const double* p, int i,
                                            double* jacobianRowMajor) const {
  const Planar2DofParameters u = full(p);
  Planar2DofProblem::TcpDerivative dReference;
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d tcpReference =
      forwardWithDerivative(geometry_, u, reference.aMm, reference.bMm, dReference);
  observationJacobianRows(u, i, tcpReference, dReference, lgpRotation(u[phi]), jacobianRowMajor, 1,
                          parameterCount());
}

void Planar2DofProblem::jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const {
  const Planar2DofParameters u = full(p.data());
  jacobian.resize(rowCount(), parameterCount());
  Planar2DofProblem::TcpDerivative dReference;
  const Planar2DofSample& reference = samples_[static_cast<std::size_t>(reference_)];
  const Eigen::Vector2d tcpReference =
      forwardWithDerivative(geometry_, u, reference.aMm, reference.bMm, dReference);
  const Eigen::Matrix2d rotation = lgpRotation(u[phi]);
  // Column-major: row 2i + t, column j at (2i + t) + j * rows.
  for (int i = 0; i < observationCount(); ++i) {
    observationJacobianRows(u, i, tcpReference, dReference, rotation, jacobian.data() + 2 * i,
                            static_cast<int>(jacobian.rows()), 1);
  }
}

void Planar2DofProblem::observationJacobianRows(const Planar2DofParameters& u, int i,
                                                const Eigen::Vector2d& tcpReference,
                                                const TcpDerivative& dReference,
                                                const Eigen::Matrix2d& rotation, double* out,
                                                int columnStride, int rowStride) const {
  const Planar2DofSample& sample = samples_[static_cast<std::size_t>(i)];
  Planar2DofProblem::TcpDerivative dSample;
  const Eigen::Vector2d relative =
      forwardWithDerivative(geometry_, u, sample.aMm, sample.bMm, dSample) - tcpReference;
  Planar2DofProblem::TcpDerivative full = rotation * (dSample - dReference);
  // dR/dphi = [-sin cos; -cos -sin] = [R(1, 0) R(0, 0); -R(0, 0) R(1, 0)].
  const double c = rotation(0, 0), s = rotation(0, 1);
  full.col(phi) =
      Eigen::Vector2d(-s * relative.x() + c * relative.y(), -c * relative.x() - s * relative.y());
  full.col(exK) = Eigen::Vector2d(1.0, 0.0);
  full.col(eyK) = Eigen::Vector2d(0.0, 1.0);
  for (std::size_t j = 0; j < freeIndex_.size(); ++j) {
    for (int t = 0; t < 2; ++t) {
      out[static_cast<int>(j) * columnStride + t * rowStride] = full(t, freeIndex_[j]);
    }
  }
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
