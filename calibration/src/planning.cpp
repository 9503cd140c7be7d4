#include "volcomp/calibration/planning.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "scaled_svd.hpp"
#include "variance_exchange.hpp"

namespace volcomp::calibration {
namespace {

using Matrix3 = Eigen::Matrix3d;

// The greedy start needs an invertible information matrix before r/3 points are chosen; a ridge
// this small against the candidates' total information (the identity in F coordinates) changes
// no choice once the design has full rank.
constexpr double kRidge = 1e-9;

double logDet3(const Matrix3& m) {
  const double d = m.determinant();
  return d > 0.0 ? std::log(d) : -std::numeric_limits<double>::infinity();
}

// The design state: M^-1 of the chosen points' information (plus the ridge) and, per candidate,
// P_i = F_i M^-1 F_i^T (3 x 3). Adding point s: log det M grows by log det(I + P_s); removing a
// chosen s: by log det(I - P_s). Both update M^-1 and every P_i with Woodbury's formula through
// H = F M^-1 F_s^T (all candidates' rows at once, one matrix product).
class Design {
 public:
  explicit Design(const detail::CandidateRows& c) : f_(c.rows), prior_(c.prior), p_(c.count()) {
    reset({});
  }

  /// Recomputes M^-1 and every P_i from the chosen points, so that rounding from many updates
  /// cannot accumulate.
  void reset(const std::vector<std::size_t>& chosen) {
    const Eigen::Index r = f_.cols();
    Eigen::MatrixXd information = prior_ + kRidge * Eigen::MatrixXd::Identity(r, r);
    for (std::size_t s : chosen) {
      const auto fs = f_.middleRows(3 * static_cast<Eigen::Index>(s), 3);
      information.noalias() += fs.transpose() * fs;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(information);
    inverse_ = ldlt.solve(Eigen::MatrixXd::Identity(r, r));
    logDet_ = ldlt.vectorD().array().log().sum();
    const Eigen::MatrixXd fInverse = f_ * inverse_;
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const auto rows = static_cast<Eigen::Index>(3 * i);
      p_[i] = fInverse.middleRows(rows, 3) * f_.middleRows(rows, 3).transpose();
    }
  }

  const Matrix3& p(std::size_t i) const { return p_[i]; }
  double logDet() const { return logDet_; }
  std::size_t candidates() const { return p_.size(); }

  /// Adds (sign +1) or removes (sign -1) candidate s.
  void update(std::size_t s, double sign) {
    const auto fs = f_.middleRows(3 * static_cast<Eigen::Index>(s), 3);
    const Eigen::MatrixXd inverseFsT = inverse_ * fs.transpose();  // r x 3
    const Matrix3 k = (Matrix3::Identity() + sign * p_[s]).inverse();
    logDet_ += logDet3(Matrix3::Identity() + sign * p_[s]);
    const Eigen::MatrixXd h = f_ * inverseFsT;  // 3C x 3
    inverse_.noalias() -= sign * inverseFsT * k * inverseFsT.transpose();
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const auto hi = h.middleRows(3 * static_cast<Eigen::Index>(i), 3);
      p_[i].noalias() -= sign * hi * k * hi.transpose();
    }
  }

  /// log det(I - P_s) + max over i not chosen of log det(I + P_i') after removing s, without
  /// changing the state; returns the best i and the total change.
  std::pair<std::size_t, double> bestSwap(std::size_t s, const std::vector<bool>& chosen) const {
    const auto fs = f_.middleRows(3 * static_cast<Eigen::Index>(s), 3);
    const Eigen::MatrixXd inverseFsT = inverse_ * fs.transpose();
    const Matrix3 removal = Matrix3::Identity() - p_[s];
    const Matrix3 k = removal.inverse();
    const Eigen::MatrixXd h = f_ * inverseFsT;
    std::size_t best = s;
    double bestGain = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p_.size(); ++i) {
      if (chosen[i] && i != s) continue;
      const auto hi = h.middleRows(3 * static_cast<Eigen::Index>(i), 3);
      const Matrix3 after = p_[i] + hi * k * hi.transpose();
      const double gain = logDet3(Matrix3::Identity() + after);
      if (gain > bestGain) {
        bestGain = gain;
        best = i;
      }
    }
    return {best, logDet3(removal) + bestGain};
  }

 private:
  const Eigen::MatrixXd& f_;
  const Eigen::MatrixXd& prior_;
  Eigen::MatrixXd inverse_;
  std::vector<Matrix3> p_;
  double logDet_ = 0.0;
};

void report(const PlanOptions& options, const std::string& line) {
  if (options.progress) options.progress(line);
}

}  // namespace

bool PlanOptions::isValid(std::string* error, Field* field) const {
  const auto invalid = [&](Field which, const char* expected) {
    if (error != nullptr) *error = expected;
    if (field != nullptr) *field = which;
    return false;
  };
  if (points < 1) return invalid(Field::Points, "expected N >= 1");
  if (!(noiseMm > 0.0)) return invalid(Field::Noise, "expected > 0 (mm)");
  if (!(rankTolerance > 0.0 && rankTolerance < 1.0)) {
    return invalid(Field::RankTolerance, "expected a value in (0, 1)");
  }
  if (maxPasses < 0) return invalid(Field::MaxPasses, "expected >= 0");
  return true;
}

std::vector<PlanCandidate> gridCandidates(const model::MachineModelSpec& spec,
                                          const std::array<int, 3>& nodes,
                                          const std::vector<Eigen::Vector3d>& toolsMm) {
  std::array<std::vector<double>, 3> axes;
  for (int axis = 0; axis < 3; ++axis) {
    const auto& travel = spec.travelMm[static_cast<std::size_t>(axis)];
    const int count = nodes[static_cast<std::size_t>(axis)];
    if (!travel || count < 1) {
      throw std::invalid_argument(std::string("a grid needs the travel of axis ") + "XYZ"[axis] +
                                  " and at least one node");
    }
    for (int k = 0; k < count; ++k) {
      axes[static_cast<std::size_t>(axis)].push_back(
          count == 1 ? 0.5 * ((*travel)[0] + (*travel)[1])
                     : (*travel)[0] + ((*travel)[1] - (*travel)[0]) * k / (count - 1));
    }
  }
  std::vector<PlanCandidate> candidates;
  for (const Eigen::Vector3d& tool : toolsMm) {
    for (double x : axes[0]) {
      for (double y : axes[1]) {
        for (double z : axes[2]) {
          PlanCandidate c;
          c.qMm = {x, y, z};
          c.toolMm = tool;
          candidates.push_back(c);
        }
      }
    }
  }
  return candidates;
}

MeasurementSet designMeasurements(const std::vector<PlanCandidate>& candidates,
                                  const std::vector<std::size_t>& chosen) {
  MeasurementSet set;
  set.file = "plan";
  set.hasTool = true;
  set.hasDirection = true;
  for (std::size_t i : chosen) {
    Measurement m;
    m.qMm = candidates[i].qMm;
    m.toolMm = candidates[i].toolMm;
    m.directions = candidates[i].directions;
    m.line = candidates[i].line;
    set.points.push_back(m);
  }
  return set;
}

PlanResult evaluateDesign(const config::ModelDocument& templateDocument,
                          const std::vector<PlanCandidate>& candidates,
                          const std::vector<std::size_t>& chosen, const PlanOptions& options) {
  PlanResult result;
  result.selected = chosen;
  std::vector<std::size_t> all(candidates.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  const auto everything =
      makeIdentificationProblem(templateDocument, designMeasurements(candidates, all));
  const auto design =
      makeIdentificationProblem(templateDocument, designMeasurements(candidates, chosen));
  const Eigen::VectorXd start = design->startVector();
  Eigen::MatrixXd jacobian;
  design->jacobian(start, jacobian);
  std::vector<std::string> names;
  for (const ParameterInfo& info : design->parameterInfo()) names.push_back(info.name);
  result.statistics = analyse(jacobian, Eigen::VectorXd::Zero(jacobian.rows()), names,
                              options.rankTolerance, options.identifiabilityThreshold);
  // No measurements yet: the scatter is the instrument's, not an a-posteriori estimate.
  FitStatistics& st = result.statistics;
  st.varianceFactor = options.noiseMm * options.noiseMm;
  st.covariance = st.varianceFactor * st.rangeFactor * st.rangeFactor.transpose();
  for (Eigen::Index j = 0; j < st.standardDeviation.size(); ++j) {
    if (std::isfinite(st.standardDeviation(j)))
      st.standardDeviation(j) = std::sqrt(st.covariance(j, j));
  }

  Eigen::MatrixXd candidateRows;
  everything->jacobian(start, candidateRows);
  result.candidateRank = ScaledSvd(candidateRows, options.rankTolerance).rank;
  const Eigen::MatrixXd propagated = candidateRows * st.rangeFactor;
  const Eigen::MatrixXd unseen = candidateRows * (st.columnScale.asDiagonal() * st.nullBasis);
  double sum = 0.0;
  int determined = 0;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    double squared = 0.0;
    bool seen = true;
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      const Eigen::Index row = 3 * static_cast<Eigen::Index>(i) + axis;
      squared += propagated.row(row).squaredNorm();
      // predictionUncertainty()'s criterion.
      seen = seen && (unseen.cols() == 0 || unseen.row(row).norm() <= st.nullThreshold);
    }
    const double value = options.noiseMm * std::sqrt(squared);
    result.candidateStdMm.push_back(seen ? value : std::numeric_limits<double>::quiet_NaN());
    if (!seen) {
      ++result.undetermined;
      continue;
    }
    ++determined;
    sum += value * value;
    result.maxStdMm = std::max(result.maxStdMm, value);
  }
  result.rmsStdMm = determined > 0 ? std::sqrt(sum / determined) : 0.0;
  return result;
}

PlanResult planMeasurements(const config::ModelDocument& templateDocument,
                            const std::vector<PlanCandidate>& candidates,
                            const PlanOptions& options) {
  const std::size_t count = candidates.size();
  if (options.points < 1 || static_cast<std::size_t>(options.points) > count) {
    throw std::invalid_argument(
        "the number of points must be between 1 and the number of "
        "candidates (" +
        std::to_string(count) + ")");
  }
  std::vector<std::size_t> all(count);
  for (std::size_t i = 0; i < count; ++i) all[i] = i;
  const auto problem =
      makeIdentificationProblem(templateDocument, designMeasurements(candidates, all));
  Eigen::MatrixXd jacobian;
  problem->jacobian(problem->startVector(), jacobian);
  report(options, "sensitivity of " + std::to_string(count) + " candidates to " +
                      std::to_string(jacobian.cols()) + " parameters");

  // F = J_s V_r S_r^-1 = U_r: the candidates (3 rows each) and the template's prior rows
  // (smoothness) in coordinates of what they can identify.
  detail::CandidateRows rows;
  {
    const ScaledSvd svd(jacobian, options.rankTolerance);
    const Eigen::Index r = svd.rank;
    const Eigen::MatrixXd scaled = jacobian * svd.columnScale.asDiagonal();
    const Eigen::MatrixXd f =
        scaled * svd.v.leftCols(r) * svd.singularValues.head(r).cwiseInverse().asDiagonal();
    const auto candidateRows = static_cast<Eigen::Index>(3 * count);
    rows.rows = f.topRows(candidateRows);
    const auto prior = f.bottomRows(f.rows() - candidateRows);
    rows.prior = prior.transpose() * prior;
  }
  report(options, "the candidates identify rank " + std::to_string(rows.rows.cols()) + " of " +
                      std::to_string(jacobian.cols()));

  Design design(rows);
  std::vector<bool> chosen(count, false);
  std::vector<std::size_t> selected;
  for (int k = 0; k < options.points; ++k) {
    std::size_t best = count;
    double bestGain = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < count; ++i) {
      if (chosen[i]) continue;
      const double gain = logDet3(Matrix3::Identity() + design.p(i));
      if (gain > bestGain) {
        bestGain = gain;
        best = i;
      }
    }
    design.update(best, 1.0);
    chosen[best] = true;
    selected.push_back(best);
  }
  design.reset(selected);
  report(options, "greedy start: log det " + std::to_string(design.logDet()));

  int exchanges = 0;
  for (int pass = 0; pass < options.maxPasses; ++pass) {
    int changed = 0;
    for (std::size_t& s : selected) {
      const auto [replacement, gain] = design.bestSwap(s, chosen);
      if (replacement == s || !(gain > 1e-9)) continue;
      design.update(s, -1.0);
      design.update(replacement, 1.0);
      chosen[s] = false;
      chosen[replacement] = true;
      s = replacement;
      ++changed;
    }
    exchanges += changed;
    design.reset(selected);
    report(options, "exchange pass " + std::to_string(pass + 1) + ": " + std::to_string(changed) +
                        " points exchanged, log det " + std::to_string(design.logDet()));
    if (changed == 0) break;
  }

  if (options.criterion == PlanCriterion::I) {
    // The exchange needs M positive definite; a design that leaves a prediction undetermined
    // has infinite variance whatever is exchanged, and D (which counts every identified
    // direction) is the criterion that makes it determine as much as it can.
    if (!detail::determinesEveryPrediction(rows, selected, options.rankTolerance)) {
      report(options,
             "I-optimal exchange skipped: the design does not determine every prediction "
             "(rank deficient), the D-optimal design is kept");
    } else {
      report(options, "I-optimal exchange (mean prediction variance over the candidates):");
      selected = detail::minimiseWeightedVariance(
          rows, Eigen::VectorXd::Ones(static_cast<Eigen::Index>(count)), selected,
          options.maxPasses, options.progress);
    }
  }

  PlanResult result = evaluateDesign(templateDocument, candidates, selected, options);
  design.reset(selected);
  result.logDeterminant = design.logDet();
  result.exchanges = exchanges;
  result.criterion = options.criterion;
  return result;
}

}  // namespace volcomp::calibration
