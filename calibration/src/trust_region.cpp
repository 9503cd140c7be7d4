// Levenberg-Marquardt without a robust loss (trust_region.hpp). Ceres solved these problems
// before, with central differences through its generic cost-function interface; for the few
// parameters and rows of a device or a D-H chain its per-problem set-up and per-iteration
// bookkeeping cost more than the fit, and its step control took 20 steps on the benchmark's planar
// device where MINPACK's needs 3 or 4 Jacobians. This is MINPACK's step control (scaling, trust
// radius, acceptance and tests) with the damping found from one eigendecomposition per Jacobian of
// the n x n normal matrix of the scaled Jacobian, A = Js^T Js: every trial lambda is then a sum
// over n terms (MINPACK's lmpar rotates sqrt(lambda) D into a QR factor for each; an SVD of the
// QR's triangle would serve as well at more than twice the cost for 7 parameters). Squaring the
// condition number costs nothing that matters here: the iteration only needs steps that reduce
// |r|, its fixed point (Js^T r = 0) does not depend on how A is factorised, and the statistics
// are taken afterwards from the SVD of J itself (least_squares.cpp). Directions the data cannot
// see (e_i <= rankTolerance^2 e_max, i.e. s_i <= rankTolerance s_1) take no step at all, as in
// the linear solve: damping alone would let a nonlinear model drift along them. All work arrays
// are sized once; an iteration allocates once, inside Eigen's eigensolver (its tridiagonal
// reduction; callgrind counts one malloc per compute()), besides whatever the problem's residuals
// and Jacobian do (the planar device's: nothing).

#include "trust_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <Eigen/Eigenvalues>

namespace volcomp::calibration {
namespace {

constexpr double kFunctionTolerance = 1e-14;
constexpr double kStepTolerance = 1e-12;
// Residual evaluations per Jacobian before giving up on a step (each failure shrinks Delta by at
// least half, so Delta is far below kStepTolerance long before).
constexpr int kMaxTrials = 60;

// The damped step for a trust radius in the eigenbasis of A = Js^T Js = V diag(e) V^T, with
// b = V^T g (g = Js^T r): p = -V diag(1 / (e_i + lambda)) b over the directions the data see
// (e_i > cut; the others take no step, as in the linear solve), lambda = 0 when that Gauss-Newton
// step is no longer than 1.1 Delta, else lambda > 0 such that |p| is within 10 % of Delta: Moré's
// Newton iteration on 1/|p| - 1/Delta, safeguarded by 0 <= lambda <= |b| / Delta. Each trial
// lambda costs O(n): |p|^2 = sum b_i^2 / (e_i + lambda)^2.
struct Damping {
  double lambda = 0.0;
  double stepNorm = 0.0;
};

Damping dampingFor(const Eigen::VectorXd& e, const Eigen::VectorXd& b, double delta, double cut) {
  const auto norm = [&](double lambda, double& cubed) {
    double squared = 0.0;
    cubed = 0.0;
    for (Eigen::Index i = 0; i < e.size(); ++i) {
      if (!(e(i) > cut)) continue;
      const double denominator = e(i) + lambda;
      const double p = b(i) / denominator;
      squared += p * p;
      cubed += p * p / denominator;
    }
    return std::sqrt(squared);
  };
  Damping out;
  double cubed = 0.0;
  out.stepNorm = norm(0.0, cubed);
  if (out.stepNorm <= 1.1 * delta) return out;
  double upper = b.norm() / delta;
  double lower = 0.0;
  double lambda = 0.0;
  for (int k = 0; k < 30; ++k) {
    // d|p|/dlambda = -sum p_i^2 / (e_i + lambda) / |p|.
    double next = lambda + (out.stepNorm - delta) / delta * out.stepNorm * out.stepNorm / cubed;
    if (out.stepNorm > delta) lower = std::max(lower, lambda);
    if (out.stepNorm < delta) upper = std::min(upper, lambda);
    if (!(next > lower && next < upper)) next = std::max(1e-3 * upper, std::sqrt(lower * upper));
    lambda = next;
    out.stepNorm = norm(lambda, cubed);
    out.lambda = lambda;
    if (std::abs(out.stepNorm - delta) <= 0.1 * delta) break;
  }
  return out;
}

}  // namespace

FitResult solveTrustRegion(const ResidualProblem& problem, const Eigen::VectorXd& start,
                           const SolveOptions& options) {
  FitResult result;
  result.start = start;
  result.parameters = start;
  const Eigen::Index n = problem.parameterCount();
  const Eigen::Index m = problem.rowCount();
  if (n == 0) {
    result.converged = true;
    result.termination = "no parameters to identify";
    return result;
  }
  Eigen::VectorXd& x = result.parameters;
  Eigen::VectorXd r(m), trialResiduals(m), trial(n), scale(n), p(n), g(n), b(n), ratios(n);
  Eigen::MatrixXd jacobian(m, n), normal(n, n);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(n);
  problem.residuals(x, r);
  if (!r.allFinite()) {
    result.termination = "the residuals are not finite at the start values";
    return result;
  }
  double residualNorm = r.norm();
  double delta = 0.0;
  result.termination = "iteration limit reached";
  bool done = false;
  while (!done && result.iterations < options.maxIterations) {
    problem.jacobian(x, jacobian);
    ++result.iterations;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double columnNorm = jacobian.col(j).norm();
      if (result.iterations == 1) {
        scale(j) = columnNorm > 0.0 ? columnNorm : 1.0;
      } else {
        scale(j) = std::max(scale(j), columnNorm);
      }
    }
    double scaledNorm = scale.cwiseProduct(x).norm();
    if (result.iterations == 1) delta = scaledNorm > 0.0 ? 100.0 * scaledNorm : 100.0;
    if (residualNorm == 0.0) {
      result.converged = true;
      result.termination = "the residuals are zero";
      break;
    }
    jacobian *= scale.cwiseInverse().asDiagonal();
    // Coefficient by coefficient: for n of a few the blocked product's set-up costs more.
    normal.noalias() = jacobian.transpose().lazyProduct(jacobian);
    eigen.compute(normal);
    const Eigen::VectorXd& e = eigen.eigenvalues();
    g.noalias() = jacobian.transpose() * r;
    b.noalias() = eigen.eigenvectors().transpose() * g;
    // Eigenvalues ascending; s_i <= rankTolerance * s_1 on the singular values of Js.
    const double cut = options.rankTolerance * options.rankTolerance * e(n - 1);
    if (!(e(n - 1) > 0.0) || g.norm() == 0.0) {
      result.converged = true;
      result.termination = "the gradient is zero";
      break;
    }
    for (int trialCount = 0;; ++trialCount) {
      const Damping damping = dampingFor(e, b, delta, cut);
      const double lambda = damping.lambda;
      const double stepNorm = damping.stepNorm;
      // Scaled step p = -V diag(1 / (e + lambda)) b, and |Js p|^2 = sum e_i b_i^2 / (e_i +
      // lambda)^2.
      double fittedSquared = 0.0;
      for (Eigen::Index i = 0; i < n; ++i) {
        ratios(i) = e(i) > cut ? b(i) / (e(i) + lambda) : 0.0;
        fittedSquared += e(i) > cut ? e(i) * ratios(i) * ratios(i) : 0.0;
      }
      p.noalias() = -(eigen.eigenvectors() * ratios);
      if (result.iterations == 1 && trialCount == 0) delta = std::min(delta, stepNorm);
      trial = x + p.cwiseQuotient(scale);
      problem.residuals(trial, trialResiduals);
      const double trialNorm = trialResiduals.allFinite() ? trialResiduals.norm()
                                                          : std::numeric_limits<double>::infinity();
      // MINPACK's reductions, relative to |r|^2, and its update of the radius.
      const double actual = 0.1 * trialNorm < residualNorm
                                ? 1.0 - (trialNorm / residualNorm) * (trialNorm / residualNorm)
                                : -1.0;
      const double fitted = std::sqrt(std::max(fittedSquared, 0.0)) / residualNorm;
      const double damped = std::sqrt(lambda) * stepNorm / residualNorm;
      const double predicted = fitted * fitted + 2.0 * damped * damped;
      const double directional = -(fitted * fitted + damped * damped);
      const double ratio = predicted != 0.0 ? actual / predicted : 0.0;
      if (ratio <= 0.25) {
        double factor = actual >= 0.0 ? 0.5 : 0.5 * directional / (directional + 0.5 * actual);
        if (0.1 * trialNorm >= residualNorm || factor < 0.1) factor = 0.1;
        delta = factor * std::min(delta, 10.0 * stepNorm);
      } else if (lambda == 0.0 || ratio >= 0.75) {
        delta = 2.0 * stepNorm;
      }
      const bool accepted = ratio >= 1e-4;
      if (accepted) {
        x.swap(trial);
        r.swap(trialResiduals);
        residualNorm = trialNorm;
        scaledNorm = scale.cwiseProduct(x).norm();
      }
      if (std::abs(actual) <= kFunctionTolerance && predicted <= kFunctionTolerance &&
          0.5 * ratio <= 1.0) {
        result.converged = true;
        result.termination = "the relative reduction of the sum of squares is below 1e-14";
        done = true;
      } else if (delta <= kStepTolerance * scaledNorm) {
        result.converged = true;
        result.termination = "the trust region is below 1e-12 of the scaled parameters";
        done = true;
      } else if (trialCount + 1 >= kMaxTrials) {
        result.termination = "no step reduces the residuals";
        done = true;
      }
      if (options.progress && (accepted || done)) {
        std::ostringstream line;
        line << "iteration " << result.iterations << ": |r| = " << residualNorm << ", step "
             << stepNorm;
        options.progress(line.str());
      }
      if (done || accepted) break;
    }
  }
  return result;
}

}  // namespace volcomp::calibration
