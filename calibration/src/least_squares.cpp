#include "volcomp/calibration/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <utility>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "scaled_svd.hpp"
#include "trust_region.hpp"

namespace volcomp::calibration {

// ---- ResidualProblem defaults -------------------------------------------------------------------

double ResidualProblem::parameterStep(int, double pj) const {
  return 1e-6 * std::max(1.0, std::abs(pj));
}

void ResidualProblem::observationJacobian(const double* p, int i, double* jacobianRowMajor) const {
  const int n = parameterCount();
  const int k = residualsPerObservation();
  std::vector<double> shifted(p, p + n);
  std::vector<double> plus(k), minus(k);
  for (int j = 0; j < n; ++j) {
    const double h = parameterStep(j, p[j]);
    shifted[j] = p[j] + h;
    observationResiduals(shifted.data(), i, plus.data());
    shifted[j] = p[j] - h;
    observationResiduals(shifted.data(), i, minus.data());
    shifted[j] = p[j];
    for (int row = 0; row < k; ++row) {
      jacobianRowMajor[row * n + j] = (plus[row] - minus[row]) / (2.0 * h);
    }
  }
}

void ResidualProblem::priorResiduals(const double*, double*) const {}

void ResidualProblem::priorJacobian(const double* p, double* jacobianRowMajor) const {
  const int n = parameterCount();
  const int k = priorRowCount();
  std::vector<double> shifted(p, p + n);
  std::vector<double> plus(k), minus(k);
  for (int j = 0; j < n; ++j) {
    const double h = parameterStep(j, p[j]);
    shifted[j] = p[j] + h;
    priorResiduals(shifted.data(), plus.data());
    shifted[j] = p[j] - h;
    priorResiduals(shifted.data(), minus.data());
    shifted[j] = p[j];
    for (int row = 0; row < k; ++row) {
      jacobianRowMajor[row * n + j] = (plus[row] - minus[row]) / (2.0 * h);
    }
  }
}

void ResidualProblem::residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
  const int k = residualsPerObservation();
  const int obs = observationCount();
  r.resize(rowCount());
  for (int i = 0; i < obs; ++i) observationResiduals(p.data(), i, r.data() + i * k);
  if (priorRowCount() > 0) priorResiduals(p.data(), r.data() + obs * k);
}

void ResidualProblem::jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const {
  const int n = parameterCount();
  const int k = residualsPerObservation();
  const int obs = observationCount();
  jacobian.resize(rowCount(), n);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> block(k, n);
  for (int i = 0; i < obs; ++i) {
    observationJacobian(p.data(), i, block.data());
    jacobian.middleRows(i * k, k) = block;
  }
  if (priorRowCount() > 0) {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> prior(priorRowCount(),
                                                                                 n);
    priorJacobian(p.data(), prior.data());
    jacobian.bottomRows(priorRowCount()) = prior;
  }
}

ResidualAccumulator::ResidualAccumulator(int rows) {
  stats_.rowRms = Eigen::VectorXd::Zero(rows);
  stats_.rowMax = Eigen::VectorXd::Zero(rows);
  stats_.rowMaxIndex.assign(static_cast<std::size_t>(rows), -1);
}

void ResidualAccumulator::add(const double* residuals, int index) {
  double squared = 0.0;
  for (Eigen::Index row = 0; row < stats_.rowRms.size(); ++row) {
    const double value = std::abs(residuals[row]);
    squared += value * value;
    stats_.rowRms(row) += value * value;
    if (value > stats_.rowMax(row)) {
      stats_.rowMax(row) = value;
      stats_.rowMaxIndex[static_cast<std::size_t>(row)] = index;
    }
  }
  sum_ += squared;
  ++count_;
  const double norm = std::sqrt(squared);
  if (norm > stats_.max) {
    stats_.max = norm;
    stats_.maxIndex = index;
  }
}

ResidualStats ResidualAccumulator::finish() const {
  ResidualStats out = stats_;
  if (count_ > 0) {
    out.rms = std::sqrt(sum_ / count_);
    out.rowRms = (out.rowRms / count_).cwiseSqrt();
  }
  return out;
}

void accumulateResiduals(const ResidualProblem& problem, const Eigen::VectorXd& p,
                         ResidualAccumulator& accumulator, int first) {
  const int k = problem.residualsPerObservation();
  const int rows = std::min(k, problem.statisticsRows());
  // All residuals at once: a problem may share work between its observations (residuals()).
  Eigen::VectorXd all;
  problem.residuals(p, all);
  for (int i = 0; i < problem.observationCount(); ++i) {
    double* block = all.data() + static_cast<Eigen::Index>(i) * k;
    const double weight = problem.observationWeight(i);
    const double unweight = weight > 0.0 ? 1.0 / std::sqrt(weight) : 0.0;
    for (int row = 0; row < rows; ++row) block[row] *= unweight;
    accumulator.add(block, first + i);
  }
}

ResidualStats residualStats(const ResidualProblem& problem, const Eigen::VectorXd& p) {
  ResidualAccumulator accumulator(
      std::min(problem.residualsPerObservation(), problem.statisticsRows()));
  accumulateResiduals(problem, p, accumulator);
  return accumulator.finish();
}

// ---- Scaled SVD ---------------------------------------------------------------------------------

ScaledSvd::ScaledSvd(Eigen::MatrixXd jacobian, double rankTolerance, bool withU) {
  const Eigen::Index m = jacobian.rows();
  const Eigen::Index n = jacobian.cols();
  columnScale = Eigen::VectorXd::Ones(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double norm = jacobian.col(j).norm();
    // A column without effect keeps scale 1: it shows up as a zero singular value and is named.
    if (norm > 0.0 && std::isfinite(norm)) columnScale(j) = 1.0 / norm;
  }
  jacobian *= columnScale.asDiagonal();
  if (m >= n) {
    // QR first (in place: the matrix is large): the SVD then works on an n x n triangle.
    factors = std::move(jacobian);
    Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(factors);
    householderCoefficients = qr.hCoeffs();
    const Eigen::MatrixXd r = factors.topRows(n).triangularView<Eigen::Upper>();
    Eigen::BDCSVD<Eigen::MatrixXd> svd(
        r, withU ? Eigen::ComputeFullU | Eigen::ComputeFullV : Eigen::ComputeFullV);
    singularValues = svd.singularValues();
    if (withU) uSmall = svd.matrixU();
    v = svd.matrixV();
    tall = true;
  } else {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(
        jacobian, withU ? Eigen::ComputeFullU | Eigen::ComputeFullV : Eigen::ComputeFullV);
    singularValues = Eigen::VectorXd::Zero(n);
    singularValues.head(svd.singularValues().size()) = svd.singularValues();
    if (withU) uSmall = svd.matrixU();
    v = svd.matrixV();
    tall = false;
  }
  const double largest = singularValues.size() > 0 ? singularValues(0) : 0.0;
  rank = 0;
  for (Eigen::Index i = 0; i < singularValues.size(); ++i) {
    if (largest > 0.0 && singularValues(i) > rankTolerance * largest) ++rank;
  }
}

Eigen::VectorXd ScaledSvd::projectResiduals(const Eigen::VectorXd& residuals) const {
  // U_k^T r, with U = Q [U_R; 0] for the tall case.
  if (tall) {
    Eigen::VectorXd qtr = residuals;
    qtr.applyOnTheLeft(Eigen::householderSequence(factors, householderCoefficients).adjoint());
    return uSmall.leftCols(rank).transpose() * qtr.head(uSmall.rows());
  }
  return uSmall.leftCols(rank).transpose() * residuals;
}

Eigen::VectorXd ScaledSvd::step(const Eigen::VectorXd& projected) const {
  const Eigen::VectorXd scaledStep =
      -(v.leftCols(rank) * (projected.array() / singularValues.head(rank).array()).matrix());
  return columnScale.asDiagonal() * scaledStep;
}

// ---- Analysis -----------------------------------------------------------------------------------

namespace {

std::string formatCoefficient(double value) {
  std::ostringstream out;
  out << (value >= 0 ? "+" : "") << std::setprecision(3) << value;
  return out.str();
}

// Reduced row echelon form of the null-space basis (rows = directions), complete pivoting: each
// direction then has a 1 at "its" pivot parameter and 0 at the others' pivots, which turns an
// arbitrary orthonormal basis into combinations that are as sparse as the data allow (e.g.
// {ea+eb, eha+ehb} rather than two mixtures of all four). Returns the pivot of each row.
std::vector<Eigen::Index> reducedRowEchelon(Eigen::MatrixXd& rows) {
  const Eigen::Index q = rows.rows();
  const Eigen::Index n = rows.cols();
  std::vector<bool> pivotUsed(n, false);
  std::vector<Eigen::Index> pivots;
  for (Eigen::Index r = 0; r < q; ++r) {
    Eigen::Index bestRow = r, bestCol = -1;
    double best = 0.0;
    for (Eigen::Index i = r; i < q; ++i) {
      for (Eigen::Index j = 0; j < n; ++j) {
        if (!pivotUsed[j] && std::abs(rows(i, j)) > best) {
          best = std::abs(rows(i, j));
          bestRow = i;
          bestCol = j;
        }
      }
    }
    if (bestCol < 0 || best < 1e-12) break;
    rows.row(r).swap(rows.row(bestRow));
    rows.row(r) /= rows(r, bestCol);
    for (Eigen::Index i = 0; i < q; ++i) {
      if (i != r) rows.row(i) -= rows(i, bestCol) * rows.row(r);
    }
    rows(r, bestCol) = 1.0;
    pivotUsed[bestCol] = true;
    pivots.push_back(bestCol);
  }
  return pivots;
}

std::string describe(const std::vector<std::pair<int, double>>& terms,
                     const std::vector<std::string>& names) {
  std::ostringstream out;
  if (terms.size() == 1) {
    out << names[terms[0].first]
        << " has no effect on the measured data: it cannot be identified (fix it or measure "
           "where it acts)";
    return out.str();
  }
  for (std::size_t t = 0; t < terms.size(); ++t) {
    if (t > 0) out << (t + 1 == terms.size() ? " and " : ", ");
    out << names[terms[t].first];
  }
  out << " are not separable with these data: changing them together as (";
  for (std::size_t t = 0; t < terms.size(); ++t) {
    if (t > 0) out << ", ";
    out << names[terms[t].first] << " " << formatCoefficient(terms[t].second);
  }
  out << ", in units of their sensitivities) leaves the measured residuals unchanged; fix one of "
         "them or add measurements that distinguish them";
  return out.str();
}

// Parameters whose share in every null direction is rounding noise (below the threshold) are
// taken out of the basis before it is brought to echelon form, so that the listed combinations
// hold exactly the parameters flagged as not identifiable.
std::vector<Combination> namedCombinations(const ScaledSvd& svd,
                                           const std::vector<bool>& identifiable,
                                           const std::vector<std::string>& names,
                                           double threshold) {
  const Eigen::Index n = svd.v.rows();
  const Eigen::Index k = svd.rank;
  std::vector<Combination> combinations;
  if (k >= n) return combinations;
  Eigen::MatrixXd directions = svd.v.rightCols(n - k).transpose();
  for (Eigen::Index j = 0; j < n; ++j) {
    if (identifiable[static_cast<std::size_t>(j)]) directions.col(j).setZero();
  }
  const std::vector<Eigen::Index> pivots = reducedRowEchelon(directions);
  const double largest = svd.singularValues.size() > 0 ? svd.singularValues(0) : 0.0;
  // Which shares are listed: those of at least the threshold (relative to the direction's
  // largest); a parameter not identifiable whose shares are all below it (spread over several
  // directions) is listed where its share is largest, so that every such parameter is named.
  Eigen::MatrixXd relative = directions.topRows(static_cast<Eigen::Index>(pivots.size()));
  for (Eigen::Index d = 0; d < relative.rows(); ++d) {
    relative.row(d) /= relative.row(d).cwiseAbs().maxCoeff();
  }
  const auto listed = [&](std::size_t d, Eigen::Index j) {
    const double share = std::abs(relative(static_cast<Eigen::Index>(d), j));
    if (share >= threshold) return true;
    Eigen::Index strongest = 0;
    relative.col(j).cwiseAbs().maxCoeff(&strongest);
    return share > 0.0 && strongest == static_cast<Eigen::Index>(d) &&
           relative.col(j).cwiseAbs().maxCoeff() < threshold;
  };
  for (std::size_t d = 0; d < pivots.size(); ++d) {
    const Eigen::VectorXd direction = directions.row(static_cast<Eigen::Index>(d)).transpose();
    const double largestTerm = direction.cwiseAbs().maxCoeff();
    Combination combination;
    combination.pivot = static_cast<int>(pivots[d]);
    const double pivotRaw = svd.columnScale(pivots[d]) * direction(pivots[d]);
    Eigen::VectorXd raw = Eigen::VectorXd::Zero(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      // Shares below the threshold are noise of the basis (rounding, finite differences),
      // unless the parameter would otherwise appear in no combination (see below).
      if (identifiable[static_cast<std::size_t>(j)] || !listed(d, j)) continue;
      combination.terms.emplace_back(static_cast<int>(j), direction(j) / largestTerm);
      raw(j) = svd.columnScale(j) * direction(j) / pivotRaw;
      combination.rawTerms.emplace_back(static_cast<int>(j), raw(j));
    }
    // |Js D^-1 d| = |S V^T D^-1 d|.
    const Eigen::VectorXd scaled = raw.cwiseQuotient(svd.columnScale);
    combination.residualChangePerPivotUnit =
        (svd.singularValues.asDiagonal() * (svd.v.transpose() * scaled)).norm();
    combination.relativeSingularValue =
        largest > 0.0 ? (svd.singularValues.asDiagonal() * (svd.v.transpose() * direction)).norm() /
                            direction.norm() / largest
                      : 0.0;
    combination.description = describe(combination.terms, names);
    combinations.push_back(std::move(combination));
  }
  // In the order of their first parameter: which parameter becomes a pivot, and so the order of
  // the echelon rows, depends on the basis the SVD returns for the null space, which any change
  // of the point or of the derivatives' rounding rotates.
  const auto first = [](const Combination& c) {
    return c.terms.empty() ? c.pivot : c.terms.front().first;
  };
  std::stable_sort(combinations.begin(), combinations.end(),
                   [&](const Combination& a, const Combination& b) { return first(a) < first(b); });
  return combinations;
}

}  // namespace

FitStatistics analyseFactorised(const ScaledSvd& svd, const Eigen::VectorXd& residuals,
                                const std::vector<std::string>& names, double rankTolerance,
                                double identifiabilityThreshold) {
  FitStatistics stats;
  const Eigen::Index n = svd.v.rows();
  const Eigen::Index m = residuals.size();
  const int k = svd.rank;
  stats.rank = k;
  stats.parameterCount = static_cast<int>(n);
  stats.rowCount = static_cast<int>(m);
  stats.singularValues = svd.singularValues;
  const double largest = n > 0 ? svd.singularValues(0) : 0.0;
  stats.conditionNumber = k > 0 ? largest / svd.singularValues(k - 1) : 0.0;
  const double smallest = n > 0 ? svd.singularValues(n - 1) : 0.0;
  stats.fullConditionNumber =
      smallest > 0.0 ? largest / smallest : std::numeric_limits<double>::infinity();
  stats.rss = residuals.squaredNorm();
  stats.dof = static_cast<int>(m) - k;
  stats.varianceFactor = stats.dof > 0 ? stats.rss / stats.dof : 0.0;

  stats.columnScale = svd.columnScale;
  stats.nullBasis = svd.v.rightCols(n - k);
  stats.rangeFactor = svd.columnScale.asDiagonal() * svd.v.leftCols(k) *
                      svd.singularValues.head(k).cwiseInverse().asDiagonal();
  stats.covariance = stats.varianceFactor * stats.rangeFactor * stats.rangeFactor.transpose();

  stats.identifiabilityThreshold = identifiabilityThreshold;
  stats.nullThreshold = rankTolerance * largest;
  stats.nullSpaceProjection = stats.nullBasis.rowwise().norm();
  stats.identifiable.resize(static_cast<std::size_t>(n));
  for (Eigen::Index j = 0; j < n; ++j) {
    stats.identifiable[static_cast<std::size_t>(j)] =
        stats.nullSpaceProjection(j) < identifiabilityThreshold;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  stats.standardDeviation = stats.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  stats.correlation = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool iKnown = stats.identifiable[static_cast<std::size_t>(i)];
    if (!iKnown) stats.standardDeviation(i) = nan;
    for (Eigen::Index j = 0; j < n; ++j) {
      if (!iKnown || !stats.identifiable[static_cast<std::size_t>(j)]) {
        stats.correlation(i, j) = nan;
        continue;
      }
      const double denominator =
          std::sqrt(stats.covariance(i, i)) * std::sqrt(stats.covariance(j, j));
      if (i != j) {
        stats.correlation(i, j) = denominator > 0.0 ? stats.covariance(i, j) / denominator : 0.0;
      }
    }
  }
  stats.unidentifiable =
      namedCombinations(svd, stats.identifiable, names, identifiabilityThreshold);
  return stats;
}

FitStatistics analyse(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residuals,
                      const std::vector<std::string>& names, double rankTolerance,
                      double identifiabilityThreshold) {
  const ScaledSvd svd(jacobian, rankTolerance);
  return analyseFactorised(svd, residuals, names, rankTolerance, identifiabilityThreshold);
}

namespace {

PredictionUncertainty uncertainty(const FitStatistics& statistics,
                                  const Eigen::Ref<const Eigen::RowVectorXd>& g, bool absolute) {
  PredictionUncertainty u;
  const Eigen::RowVectorXd scaled = g.cwiseProduct(statistics.columnScale.transpose());
  const double size = scaled.norm();
  const double unseen =
      statistics.nullBasis.cols() > 0 ? (scaled * statistics.nullBasis).norm() : 0.0;
  u.nullShare = size > 0.0 ? unseen / size : 0.0;
  u.determined = absolute ? unseen <= statistics.nullThreshold
                          : u.nullShare < statistics.identifiabilityThreshold;
  u.std = u.determined ? std::sqrt(statistics.varianceFactor) * (g * statistics.rangeFactor).norm()
                       : std::numeric_limits<double>::quiet_NaN();
  return u;
}

}  // namespace

PredictionUncertainty predictionUncertainty(const FitStatistics& statistics,
                                            const Eigen::Ref<const Eigen::RowVectorXd>& g) {
  return uncertainty(statistics, g, true);
}

PredictionUncertainty functionUncertainty(const FitStatistics& statistics,
                                          const Eigen::Ref<const Eigen::RowVectorXd>& g) {
  return uncertainty(statistics, g, false);
}

// ---- Solve --------------------------------------------------------------------------------------

namespace {

std::vector<std::string> parameterNames(const ResidualProblem& problem) {
  std::vector<std::string> names;
  for (int j = 0; j < problem.parameterCount(); ++j) names.push_back(problem.parameterName(j));
  return names;
}

void report(const SolveOptions& options, const std::string& line) {
  if (options.progress) options.progress(line);
}

FitResult solveLinear(const ResidualProblem& problem, const Eigen::VectorXd& start,
                      const SolveOptions& options) {
  FitResult result;
  result.start = start;
  result.parameters = start;
  result.linearisedAt = start;
  Eigen::VectorXd r;
  problem.residuals(start, r);
  Eigen::MatrixXd jacobian;
  problem.jacobian(start, jacobian);
  report(options, "sensitivity matrix built");
  const Eigen::Index rows = jacobian.rows(), columns = jacobian.cols();
  const ScaledSvd svd(std::move(jacobian), options.rankTolerance);
  report(options, "factorised " + std::to_string(rows) + " x " + std::to_string(columns) +
                      ": rank " + std::to_string(svd.rank) + " of " + std::to_string(columns));
  const double absoluteTolerance =
      1e-13 * std::sqrt(static_cast<double>(std::max<Eigen::Index>(1, r.size())));
  result.termination = "iteration limit reached";
  for (int iteration = 1; iteration <= options.maxIterations; ++iteration) {
    const Eigen::VectorXd explainable = svd.projectResiduals(r);
    if (explainable.norm() <= std::max(1e-10 * r.norm(), absoluteTolerance)) {
      result.converged = true;
      result.termination = "the residual has no component the parameters can still explain";
      break;
    }
    result.parameters += svd.step(explainable);
    problem.residuals(result.parameters, r);
    result.iterations = iteration;
    std::ostringstream line;
    line << "iteration " << iteration << ": |r| = " << r.norm();
    report(options, line.str());
  }
  result.statistics = analyseFactorised(svd, r, parameterNames(problem), options.rankTolerance,
                                        options.identifiabilityThreshold);
  return result;
}

}  // namespace

FitResult solve(const ResidualProblem& problem, const Eigen::VectorXd& start,
                const SolveOptions& options) {
  const bool nonlinear =
      options.method == Method::LevenbergMarquardt || options.loss != RobustLoss::None;
  FitResult result;
  if (nonlinear) {
    // Without a robust loss the dense trust region (MINPACK's step control) is the faster;
    // Ceres keeps the robust losses, which act per observation block.
    result = options.loss == RobustLoss::None ? solveTrustRegion(problem, start, options)
                                              : solveLevenbergMarquardt(problem, start, options);
    Eigen::VectorXd r;
    problem.residuals(result.parameters, r);
    Eigen::MatrixXd jacobian;
    problem.jacobian(result.parameters, jacobian);
    ScaledSvd svd(std::move(jacobian), options.rankTolerance, false);
    // The same policy as the linear method: whatever Levenberg-Marquardt's path left along the
    // directions the data cannot see is taken back to the start values (scaled units), which
    // changes the residuals only to second order.
    if (svd.rank < svd.v.cols()) {
      const Eigen::MatrixXd nullBasis = svd.v.rightCols(svd.v.cols() - svd.rank);
      const Eigen::VectorXd change = (result.parameters - start).cwiseQuotient(svd.columnScale);
      result.parameters -=
          svd.columnScale.cwiseProduct(nullBasis * (nullBasis.transpose() * change));
      problem.residuals(result.parameters, r);
    }
    result.statistics = analyseFactorised(svd, r, parameterNames(problem), options.rankTolerance,
                                          options.identifiabilityThreshold);
    result.linearisedAt = result.parameters;
  } else {
    result = solveLinear(problem, start, options);
  }
  result.names = parameterNames(problem);
  result.before = residualStats(problem, start);
  result.after = residualStats(problem, result.parameters);
  return result;
}

}  // namespace volcomp::calibration
