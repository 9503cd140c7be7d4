#include "volcomp/calibration/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <Eigen/QR>
#include <Eigen/SVD>

#include "scaled_svd.hpp"

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

ResidualStats residualStats(const ResidualProblem& problem, const Eigen::VectorXd& p) {
  const int k = problem.residualsPerObservation();
  const int rows = std::min(k, problem.statisticsRows());
  std::vector<double> block(k);
  ResidualStats stats;
  double sum = 0.0;
  const int obs = problem.observationCount();
  for (int i = 0; i < obs; ++i) {
    problem.observationResiduals(p.data(), i, block.data());
    double squared = 0.0;
    for (int row = 0; row < rows; ++row) squared += block[row] * block[row];
    const double weight = problem.observationWeight(i);
    const double norm = weight > 0.0 ? std::sqrt(squared / weight) : 0.0;
    sum += norm * norm;
    if (norm > stats.max) {
      stats.max = norm;
      stats.maxIndex = i;
    }
  }
  stats.rms = obs > 0 ? std::sqrt(sum / obs) : 0.0;
  return stats;
}

// ---- Scaled SVD ---------------------------------------------------------------------------------

ScaledSvd::ScaledSvd(Eigen::MatrixXd jacobian, double rankTolerance) {
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
    Eigen::BDCSVD<Eigen::MatrixXd> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    singularValues = svd.singularValues();
    uSmall = svd.matrixU();
    v = svd.matrixV();
    tall = true;
  } else {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullU | Eigen::ComputeFullV);
    singularValues = Eigen::VectorXd::Zero(n);
    singularValues.head(svd.singularValues().size()) = svd.singularValues();
    uSmall = svd.matrixU();
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
    const Eigen::HouseholderSequence<Eigen::MatrixXd, Eigen::VectorXd> q(factors,
                                                                         householderCoefficients);
    qtr.applyOnTheLeft(q.transpose());
    return uSmall.leftCols(rank).transpose() * qtr.head(uSmall.rows());
  }
  return uSmall.leftCols(rank).transpose() * residuals;
}

Eigen::VectorXd ScaledSvd::step(const Eigen::VectorXd& residuals) const {
  const Eigen::VectorXd projected = projectResiduals(residuals);
  const Eigen::VectorXd scaledStep =
      -(v.leftCols(rank) * (projected.array() / singularValues.head(rank).array()).matrix());
  return columnScale.asDiagonal() * scaledStep;
}

// ---- Analysis -----------------------------------------------------------------------------------

namespace {

std::string formatCoefficient(double value) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << (value >= 0 ? "+" : "") << value;
  return out.str();
}

// Reduced row echelon form of the null-space basis (rows = directions): each direction then has
// a 1 at "its" pivot parameter and 0 at the others' pivots, which turns an arbitrary orthonormal
// basis into combinations that are as sparse as the data allow (e.g. {ea+eb, eha+ehb} rather than
// two mixtures of all four).
Eigen::MatrixXd reducedRowEchelon(Eigen::MatrixXd rows) {
  const Eigen::Index q = rows.rows();
  const Eigen::Index n = rows.cols();
  std::vector<bool> pivotUsed(n, false);
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
    pivotUsed[bestCol] = true;
  }
  return rows;
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
  out << ", in units of their sensitivities) leaves every residual unchanged; fix one of them or "
         "add measurements that distinguish them";
  return out.str();
}

}  // namespace

FitStatistics analyseFactorised(const ScaledSvd& svd, const Eigen::VectorXd& residuals,
                                const std::vector<std::string>& names) {
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

  const Eigen::MatrixXd vk = svd.v.leftCols(k);
  const Eigen::VectorXd inverseSquared = svd.singularValues.head(k).array().square().inverse();
  const Eigen::MatrixXd scaledCovariance = vk * inverseSquared.asDiagonal() * vk.transpose();
  stats.covariance = stats.varianceFactor * (svd.columnScale.asDiagonal() * scaledCovariance *
                                             svd.columnScale.asDiagonal());
  stats.standardDeviation = stats.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  stats.correlation = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double denominator = stats.standardDeviation(i) * stats.standardDeviation(j);
      if (i != j) {
        stats.correlation(i, j) = denominator > 0.0 ? stats.covariance(i, j) / denominator : 0.0;
      }
    }
  }

  stats.identifiable.assign(n, true);
  if (k < n) {
    const Eigen::MatrixXd directions = reducedRowEchelon(svd.v.rightCols(n - k).transpose());
    for (Eigen::Index d = 0; d < directions.rows(); ++d) {
      const Eigen::VectorXd direction = directions.row(d).transpose();
      const double largestTerm = direction.cwiseAbs().maxCoeff();
      if (!(largestTerm > 0.0)) continue;
      Combination combination;
      for (Eigen::Index j = 0; j < n; ++j) {
        const double coefficient = direction(j) / largestTerm;
        if (std::abs(coefficient) >= 0.1) {
          combination.terms.emplace_back(static_cast<int>(j), coefficient);
          stats.identifiable[j] = false;
        }
      }
      combination.relativeSingularValue =
          largest > 0.0
              ? (svd.singularValues.asDiagonal() * (svd.v.transpose() * direction)).norm() /
                    direction.norm() / largest
              : 0.0;
      combination.description = describe(combination.terms, names);
      stats.unidentifiable.push_back(std::move(combination));
    }
  }
  return stats;
}

FitStatistics analyse(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residuals,
                      const std::vector<std::string>& names, double rankTolerance) {
  const ScaledSvd svd(jacobian, rankTolerance);
  return analyseFactorised(svd, residuals, names);
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
    result.parameters += svd.step(r);
    problem.residuals(result.parameters, r);
    result.iterations = iteration;
    std::ostringstream line;
    line << "iteration " << iteration << ": |r| = " << r.norm();
    report(options, line.str());
  }
  result.statistics = analyseFactorised(svd, r, parameterNames(problem));
  return result;
}

}  // namespace

FitResult solve(const ResidualProblem& problem, const Eigen::VectorXd& start,
                const SolveOptions& options) {
  const bool nonlinear =
      options.method == Method::LevenbergMarquardt || options.loss != RobustLoss::None;
  FitResult result;
  if (nonlinear) {
    result = solveLevenbergMarquardt(problem, start, options);
    Eigen::VectorXd r;
    problem.residuals(result.parameters, r);
    Eigen::MatrixXd jacobian;
    problem.jacobian(result.parameters, jacobian);
    result.statistics = analyse(jacobian, r, parameterNames(problem), options.rankTolerance);
  } else {
    result = solveLinear(problem, start, options);
  }
  result.names = parameterNames(problem);
  result.before = residualStats(problem, start);
  result.after = residualStats(problem, result.parameters);
  return result;
}

}  // namespace volcomp::calibration
