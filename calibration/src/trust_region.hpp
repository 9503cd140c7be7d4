#pragma once
// Internal: Levenberg-Marquardt without a robust loss, dense, in MINPACK's trust-region form.

#include <Eigen/Core>

#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

/// Moré's Levenberg-Marquardt (MINPACK lmder): scaling D = the largest column norms of J seen so
/// far, a trust radius Delta on |D dp| grown or shrunk by the ratio of actual to predicted
/// reduction, the damping lambda chosen so that |D dp| is within 10 % of Delta (from the
/// eigendecomposition of Js^T Js, Js = J D^-1; directions with s_i <= rankTolerance s_1 take no
/// step). Stops when the relative reduction of |r|^2, both actual and predicted, is at most 1e-14,
/// or when Delta is at most 1e-12 |D p|. Returns parameters, iterations (Jacobians evaluated),
/// convergence and the reason; solve() fills the statistics.
FitResult solveTrustRegion(const ResidualProblem& problem, const Eigen::VectorXd& start,
                           const SolveOptions& options);

}  // namespace volcomp::calibration
