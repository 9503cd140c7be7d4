#include "variance_exchange.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace volcomp::calibration::detail {
namespace {

using Matrix3 = Eigen::Matrix3d;

// A removal that would leave M this close to singular (smallest eigenvalue of I - P_s) is never
// made: the design would stop determining some prediction.
constexpr double kKeepRank = 1e-8;

Eigen::Index first(std::size_t i) {
  return 3 * static_cast<Eigen::Index>(i);
}

// The exchange state in coordinates where the criterion is trace(M^-1): M^-1, G = F M^-1 and per
// candidate P_i = F_i M^-1 F_i^T and Q_i = G_i G_i^T (Q_i is what adding i removes from the
// trace, before the (I + P_i)^-1 of Woodbury's formula).
class TraceExchange {
 public:
  explicit TraceExchange(const CandidateRows& c) : c_(c), p_(c.count()), q_(c.count()) {}

  /// Recomputes the state from the design (so that rounding cannot accumulate over updates);
  /// false when the design does not make M positive definite.
  bool reset(const std::vector<std::size_t>& design) {
    const Eigen::MatrixXd m = information(c_, design);
    const Eigen::LLT<Eigen::MatrixXd> llt(m);
    if (llt.info() != Eigen::Success) return false;
    inverse_ = llt.solve(Eigen::MatrixXd::Identity(m.rows(), m.cols()));
    if (!inverse_.allFinite()) return false;
    g_.noalias() = c_.rows * inverse_;
    refresh();
    return true;
  }

  double trace() const { return inverse_.trace(); }

  /// The best exchange for chosen point s: the candidate and the change of trace(M^-1) (+inf
  /// when removing s would make M singular).
  std::pair<std::size_t, double> bestSwap(std::size_t s, const std::vector<bool>& chosen) const {
    const Eigen::MatrixXd a = g_.middleRows(first(s), 3).transpose();  // M^-1 F_s^T
    const Matrix3 removal = Matrix3::Identity() - p_[s];
    const Eigen::SelfAdjointEigenSolver<Matrix3> check(removal);
    if (check.eigenvalues().minCoeff() < kKeepRank) {
      return {s, std::numeric_limits<double>::infinity()};
    }
    const Matrix3 k = removal.inverse();
    const Matrix3 s3 = a.transpose() * a;
    const double removalCost = (k * s3).trace();
    const Eigen::MatrixXd h = c_.rows * a;  // F_i M^-1 F_s^T
    const Eigen::MatrixXd w = g_ * a;       // F_i M^-2 F_s^T
    const Matrix3 ksk = k * s3 * k;
    std::size_t best = s;
    double bestGain = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (chosen[i]) continue;
      const Matrix3 hi = h.middleRows(first(i), 3);
      const Matrix3 wi = w.middleRows(first(i), 3);
      const Matrix3 hk = hi * k;
      const Matrix3 pAfter = p_[i] + hk * hi.transpose();
      const Matrix3 cross = wi * hk.transpose();
      const Matrix3 qAfter = q_[i] + cross + cross.transpose() + hi * ksk * hi.transpose();
      const double gain = (Matrix3::Identity() + pAfter).ldlt().solve(qAfter).trace();
      if (gain > bestGain) {
        bestGain = gain;
        best = i;
      }
    }
    return {best, removalCost - bestGain};
  }

  /// Replaces chosen point s by candidate i (two rank-3 updates of M^-1 and G).
  void swap(std::size_t s, std::size_t i) {
    update(s, -1.0);
    update(i, 1.0);
    refresh();
  }

 private:
  void update(std::size_t s, double sign) {
    const Eigen::MatrixXd a = g_.middleRows(first(s), 3).transpose();
    const Matrix3 ps = g_.middleRows(first(s), 3) * c_.rows.middleRows(first(s), 3).transpose();
    const Matrix3 k = (Matrix3::Identity() + sign * ps).inverse();
    const Eigen::MatrixXd h = c_.rows * a;
    inverse_.noalias() -= sign * (a * k * a.transpose());
    g_.noalias() -= sign * (h * k * a.transpose());
  }

  void refresh() {
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const auto gi = g_.middleRows(first(i), 3);
      p_[i].noalias() = gi * c_.rows.middleRows(first(i), 3).transpose();
      q_[i].noalias() = gi * gi.transpose();
    }
  }

  const CandidateRows& c_;
  Eigen::MatrixXd inverse_;
  Eigen::MatrixXd g_;
  std::vector<Matrix3> p_;
  std::vector<Matrix3> q_;
};

void tell(const std::function<void(const std::string&)>& progress, const std::string& line) {
  if (progress) progress(line);
}

std::string number(double value) {
  std::ostringstream text;
  text.precision(4);
  text << value;
  return text.str();
}

}  // namespace

Eigen::MatrixXd information(const CandidateRows& c, const std::vector<std::size_t>& design) {
  Eigen::MatrixXd m = c.prior;
  for (std::size_t d : design) {
    const auto fd = c.rows.middleRows(first(d), 3);
    m.noalias() += fd.transpose() * fd;
  }
  return m;
}

bool determinesEveryPrediction(const CandidateRows& c, const std::vector<std::size_t>& design,
                               double rankTolerance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(information(c, design),
                                                             Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  return values.size() > 0 && values(0) > rankTolerance * rankTolerance * values(values.size() - 1);
}

std::vector<double> predictionVariances(const CandidateRows& candidates,
                                        const std::vector<std::size_t>& design) {
  const Eigen::LLT<Eigen::MatrixXd> llt(information(candidates, design));
  std::vector<double> v(candidates.count(), std::numeric_limits<double>::quiet_NaN());
  if (llt.info() != Eigen::Success) return v;
  // v_i = |F_i L^-T|^2 with M = L L^T.
  Eigen::MatrixXd x = candidates.rows;
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(x);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = x.middleRows(first(i), 3).squaredNorm();
  return v;
}

std::vector<std::size_t> minimiseWeightedVariance(
    const CandidateRows& candidates, const Eigen::VectorXd& weights,
    std::vector<std::size_t> design, int maxPasses,
    const std::function<void(const std::string&)>& progress) {
  const Eigen::Index r = candidates.rows.cols();
  // W = sum w_i F_i^T F_i (+ the prior's share and a trace-relative ridge, so that R exists
  // when the weights vanish on a direction), then F~ = F R^-1.
  Eigen::MatrixXd rowWeights(candidates.rows.rows(), 1);
  for (std::size_t i = 0; i < candidates.count(); ++i)
    rowWeights.middleRows(first(i), 3).setConstant(weights(static_cast<Eigen::Index>(i)));
  Eigen::MatrixXd w =
      candidates.rows.transpose() * (rowWeights.col(0).asDiagonal() * candidates.rows);
  w += 1e-9 * (w.trace() / static_cast<double>(r)) * Eigen::MatrixXd::Identity(r, r);
  const Eigen::LLT<Eigen::MatrixXd> llt(w);
  if (llt.info() != Eigen::Success) return design;
  CandidateRows scaled{candidates.rows, candidates.prior};
  const auto rFactor = llt.matrixU();
  rFactor.solveInPlace<Eigen::OnTheRight>(scaled.rows);
  rFactor.solveInPlace<Eigen::OnTheRight>(scaled.prior);
  rFactor.transpose().solveInPlace(scaled.prior);

  // trace(M~^-1) = sum_i w_i v_i; shown per unit weight, i.e. the weighted mean variance.
  const double totalWeight = weights.sum();
  TraceExchange state(scaled);
  if (!state.reset(design)) return design;
  std::vector<bool> chosen(candidates.count(), false);
  for (std::size_t d : design) chosen[d] = true;
  for (int pass = 0; pass < maxPasses; ++pass) {
    int changed = 0;
    for (std::size_t& s : design) {
      const auto [replacement, change] = state.bestSwap(s, chosen);
      if (replacement == s || !(change < -1e-9 * state.trace())) continue;
      state.swap(s, replacement);
      chosen[s] = false;
      chosen[replacement] = true;
      s = replacement;
      ++changed;
    }
    if (!state.reset(design)) break;
    tell(progress, "  pass " + std::to_string(pass + 1) + ": " + std::to_string(changed) +
                       " points exchanged, mean prediction variance " +
                       number(state.trace() / totalWeight) + " sigma^2");
    if (changed == 0) break;
  }
  return design;
}

}  // namespace volcomp::calibration::detail
