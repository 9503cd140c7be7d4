#pragma once
// The planar 2-DOF device's benchmark case (Hanak, Zirn and Ruoff: 7 parameters, 25 points from
// the paper's table 2 values with 1.8 um of reading noise, fitted from the paper's start) and its
// anchor: Eigen's port of MINPACK's lmder (unsupported/Eigen/NonLinearOptimization), a library we
// did not write, on the same residuals and the same analytic Jacobian, with the covariance as a
// MINPACK user computes it (s0^2 (J^T J)^-1 from a QR of J at the solution).

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>
#include <unsupported/Eigen/NonLinearOptimization>

#include "volcomp/calibration/planar2dof.hpp"

namespace volcomp::bench {

inline std::vector<calibration::Planar2DofSample> planarData() {
  using namespace volcomp::calibration;
  constexpr double kDeg = std::numbers::pi / 180.0;
  const Planar2DofParameters truth{0.30, 0.10,          1.53,    0.13,  0.0,
                                   0.0,  -0.184 * kDeg, -2.1e-3, 0.7e-3};
  std::mt19937 generator(3);
  std::normal_distribution<double> noise(0.0, 1.8e-3);
  const double c = std::cos(truth[phi]), s = std::sin(truth[phi]);
  std::vector<Planar2DofSample> samples;
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      const Eigen::Vector2d tcp(-20.0 + 10.0 * column, 180.0 + 10.0 * row);
      const Eigen::Vector2d readings = planar2DofInverse({}, truth, tcp);
      Planar2DofSample sample{
          readings.x(), readings.y(),
          Eigen::Vector2d(c * tcp.x() + s * tcp.y(), -s * tcp.x() + c * tcp.y())};
      if (row + column > 0) {
        const double dy = noise(generator);  // drawn in this order whatever the compiler
        sample.lgpMm += Eigen::Vector2d(noise(generator), dy);
      }
      samples.push_back(sample);
    }
  }
  samples[0].lgpMm -= Eigen::Vector2d(truth[exK], truth[eyK]);
  return samples;
}

inline calibration::Planar2DofParameters planarStart() {
  constexpr double kDeg = std::numbers::pi / 180.0;
  return {0.1, 0.1, 1.0, 0.1, 0.0, 0.0, 0.057 * kDeg, 3e-3, 3e-3};
}

// Eigen's functor interface over the product's residuals and Jacobian.
struct PlanarFunctor {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const calibration::Planar2DofProblem& problem;
  int inputs() const { return problem.parameterCount(); }
  int values() const { return problem.rowCount(); }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& r) const {
    problem.residuals(x, r);
    return 0;
  }
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& j) const {
    problem.jacobian(x, j);
    return 0;
  }
};

struct AnchorFit {
  Eigen::VectorXd parameters;
  Eigen::VectorXd standardDeviation;
  int iterations = 0;   // Jacobians evaluated
  int evaluations = 0;  // residual vectors evaluated
  int status = 0;
};

// MINPACK's defaults except the tolerances, set to the product's (trust_region.cpp): relative
// reduction 1e-14, radius 1e-12 of the scaled parameters.
inline AnchorFit anchorFit(const calibration::Planar2DofProblem& problem,
                           const Eigen::VectorXd& start) {
  PlanarFunctor functor{problem};
  Eigen::LevenbergMarquardt<PlanarFunctor> lm(functor);
  lm.parameters.ftol = 1e-14;
  lm.parameters.xtol = 1e-12;
  AnchorFit fit;
  fit.parameters = start;
  fit.status = static_cast<int>(lm.minimize(fit.parameters));
  fit.iterations = static_cast<int>(lm.njev);
  fit.evaluations = static_cast<int>(lm.nfev);
  Eigen::VectorXd r;
  problem.residuals(fit.parameters, r);
  Eigen::MatrixXd j;
  problem.jacobian(fit.parameters, j);
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(j);
  const Eigen::Index n = j.cols();
  const Eigen::MatrixXd rInverse =
      qr.matrixR().topLeftCorner(n, n).triangularView<Eigen::Upper>().solve(
          Eigen::MatrixXd::Identity(n, n));
  const double s0Squared = r.squaredNorm() / static_cast<double>(j.rows() - n);
  const Eigen::MatrixXd covariance = qr.colsPermutation() *
                                     (s0Squared * rInverse * rInverse.transpose()) *
                                     qr.colsPermutation().transpose();
  fit.standardDeviation = covariance.diagonal().cwiseSqrt();
  return fit;
}

}  // namespace volcomp::bench
