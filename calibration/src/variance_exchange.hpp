#pragma once
// Internal: the exchange on the prediction variance behind `volcomp plan --criterion i`.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace volcomp::calibration::detail {

/// The candidates in the coordinates of what they can identify: rows 3i..3i+2 of `rows` are
/// candidate i (F_i, 3 x r), `prior` is the information every design has anyway (smoothness rows,
/// r x r, possibly zero). The prediction variance of the 3-D error at candidate i, in units of the
/// instrument's variance, is v_i = trace(F_i M^-1 F_i^T) with M = prior + sum over the design of
/// F_d^T F_d.
struct CandidateRows {
  Eigen::MatrixXd rows;
  Eigen::MatrixXd prior;
  std::size_t count() const { return static_cast<std::size_t>(rows.rows() / 3); }
};

/// M = prior + sum over the design of F_d^T F_d.
Eigen::MatrixXd information(const CandidateRows& candidates,
                            const std::vector<std::size_t>& design);

/// Whether M has full rank r: its singular values sqrt(eig M) above rankTolerance times the
/// largest (the relative threshold of the fit's rank decision).
bool determinesEveryPrediction(const CandidateRows& candidates,
                               const std::vector<std::size_t>& design, double rankTolerance);

/// v_i for every candidate (NaN for all when M is singular).
std::vector<double> predictionVariances(const CandidateRows& candidates,
                                        const std::vector<std::size_t>& design);

/// Minimises the weighted mean prediction variance sum_i w_i v_i (I-optimal for w = 1) by
/// exchanging a chosen point for a candidate while the criterion falls: with
/// W = sum_i w_i F_i^T F_i = R^T R the criterion is trace(M~^-1) in the coordinates F R^-1, and a
/// removal or an addition changes it by an exact rank-3 (Woodbury) update. `design` must
/// determine every prediction (M positive definite); it is returned unchanged otherwise.
std::vector<std::size_t> minimiseWeightedVariance(
    const CandidateRows& candidates, const Eigen::VectorXd& weights,
    std::vector<std::size_t> design, int maxPasses,
    const std::function<void(const std::string&)>& progress);

}  // namespace volcomp::calibration::detail
