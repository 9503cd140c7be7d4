#pragma once
/// Weighted least squares for identification: the residual-problem interface, the linear
/// (sensitivity-matrix) solve with an explicit rank policy, and the statistics every fit reports.
///
/// Notation. p (n) the parameters, r(p) (m) the weighted residuals (predicted - measured, times
/// sqrt(weight)), J = dr/dp. Columns are scaled to unit norm, Js = J D with D = diag(1/|J_j|), so
/// that the rank decision does not depend on the units of the parameters. With the SVD
/// Js = U S V^T and s_1 >= s_2 >= ..., the numerical rank is k = #{ s_i > rankTolerance * s_1 }.
/// Step (minimum norm in scaled units): dp = -D V_k S_k^-1 U_k^T r.
/// Covariance: C = s0^2 D V_k S_k^-2 V_k^T D with the a-posteriori variance factor
/// s0^2 = |r|^2 / (m - k) (so sigma scales with the observed scatter; with weights 1/sigma^2,
/// s0^2 is chi^2/dof and should be near 1). Columns k+1..n of V span the directions the data
/// cannot see; they are reported as named parameter combinations.

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace volcomp::calibration {

/// A least-squares problem made of observation blocks (one per measured point, all the same size)
/// plus optional prior rows (regularisation such as table smoothness, never robustified).
class ResidualProblem {
 public:
  virtual ~ResidualProblem() = default;
  virtual int parameterCount() const = 0;
  virtual int observationCount() const = 0;
  virtual int residualsPerObservation() const = 0;
  /// Weighted residuals (predicted - measured) * sqrt(weight) of observation i at parameters p.
  virtual void observationResiduals(const double* p, int i, double* r) const = 0;
  /// Row-major residualsPerObservation() x parameterCount() Jacobian of observation i.
  /// Default: central differences with parameterStep().
  virtual void observationJacobian(const double* p, int i, double* jacobianRowMajor) const;
  /// Prior rows (appended after all observation rows).
  virtual int priorRowCount() const { return 0; }
  virtual void priorResiduals(const double* p, double* r) const;
  virtual void priorJacobian(const double* p, double* jacobianRowMajor) const;
  /// Name of parameter j for reports, e.g. "EXX c1" or "eLa".
  virtual std::string parameterName(int j) const = 0;
  /// Finite-difference step for parameter j around value pj.
  virtual double parameterStep(int j, double pj) const;
  /// Weight of observation i (residuals are divided by sqrt(weight) for the RMS/max statistics).
  virtual double observationWeight(int) const { return 1.0; }
  /// How many leading rows of a block form the "position" whose norm the statistics report.
  virtual int statisticsRows() const { return residualsPerObservation(); }

  /// All rows stacked: observations in order, then prior rows.
  int rowCount() const { return observationCount() * residualsPerObservation() + priorRowCount(); }
  void residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const;
  /// Full Jacobian, stacked like residuals(). Override when a faster form exists.
  virtual void jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const;
};

/// Residual size statistics, unweighted, over observation blocks (norm of the statistics rows).
struct ResidualStats {
  double rms = 0.0;
  double max = 0.0;
  int maxIndex = -1;
};
ResidualStats residualStats(const ResidualProblem& problem, const Eigen::VectorXd& p);

/// A direction in parameter space the data cannot see: residuals do not change along it.
struct Combination {
  /// Coefficients in scaled units (each parameter times its column norm), largest |value| = 1;
  /// parameters below 0.1 are dropped.
  std::vector<std::pair<int, double>> terms;
  /// Relative singular value of the direction (s_i / s_1).
  double relativeSingularValue = 0.0;
  /// In words, e.g. "ea and eb are not separable (ea +1.00, eb +1.00 leave the residuals
  /// unchanged)".
  std::string description;
};

/// Rank analysis and statistics of a fit at given parameters.
struct FitStatistics {
  int rank = 0;
  int parameterCount = 0;
  int rowCount = 0;
  /// Singular values of the column-scaled Jacobian, descending.
  Eigen::VectorXd singularValues;
  /// s_1 / s_k over the retained singular values (rank k); the full ratio s_1 / s_n is
  /// fullConditionNumber (infinite when s_n = 0).
  double conditionNumber = 0.0;
  double fullConditionNumber = 0.0;
  /// Sum of squared weighted residuals, degrees of freedom (rows - rank), s0^2 = rss / dof.
  double rss = 0.0;
  int dof = 0;
  double varianceFactor = 0.0;
  Eigen::MatrixXd covariance;
  Eigen::VectorXd standardDeviation;
  Eigen::MatrixXd correlation;
  /// Per parameter: false when it has weight >= 0.1 in a combination the data cannot see (its
  /// value is then the minimum-norm choice and its sigma is not meaningful).
  std::vector<bool> identifiable;
  std::vector<Combination> unidentifiable;
};

enum class Method {
  /// Sensitivity matrix at the start values, factorised once; the exact residual is re-evaluated
  /// and the correction iterated with the same factorisation (for models linear in their
  /// parameters up to second-order terms, e.g. the 21-component model).
  Linear,
  /// Levenberg-Marquardt on the exact model (Ceres), with optional robust loss.
  LevenbergMarquardt,
};

enum class RobustLoss { None, Huber, Cauchy };

struct SolveOptions {
  Method method = Method::Linear;
  /// Relative singular-value threshold of the rank policy (scaled Jacobian).
  double rankTolerance = 1e-7;
  int maxIterations = 100;
  /// Stop when the scaled step |D^-1 dp| is below this (linear method).
  double stepTolerance = 1e-12;
  RobustLoss loss = RobustLoss::None;
  /// Scale of the robust loss in residual units (mm): residuals beyond it are down-weighted.
  double lossScale = 0.01;
  /// Receives one line per iteration (progress); may be empty.
  std::function<void(const std::string&)> progress;
};

struct FitResult {
  Eigen::VectorXd start;
  Eigen::VectorXd parameters;
  std::vector<std::string> names;
  int iterations = 0;
  bool converged = false;
  /// Why the iteration stopped, in words.
  std::string termination;
  ResidualStats before;
  ResidualStats after;
  FitStatistics statistics;
};

/// Rank analysis, covariance and unidentifiable combinations from J and r at the solution.
FitStatistics analyse(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residuals,
                      const std::vector<std::string>& names, double rankTolerance);

/// Solves the problem from `start` with options.method and fills every statistic.
FitResult solve(const ResidualProblem& problem, const Eigen::VectorXd& start,
                const SolveOptions& options = {});

/// Levenberg-Marquardt with Ceres (used by solve() for Method::LevenbergMarquardt). Returns the
/// parameters, iterations, convergence and termination text; statistics are filled by solve().
FitResult solveLevenbergMarquardt(const ResidualProblem& problem, const Eigen::VectorXd& start,
                                  const SolveOptions& options);

}  // namespace volcomp::calibration
