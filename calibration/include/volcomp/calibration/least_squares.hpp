#pragma once
/// Weighted least squares for identification: the residual-problem interface, the linear
/// (sensitivity-matrix) solve with an explicit rank policy, and the statistics every fit reports.
///
/// Notation. p (n) the parameters, r(p) (m) the weighted residuals (predicted - measured, times
/// sqrt(weight)), J = dr/dp. Columns are scaled to unit norm, Js = J D with D = diag(1/|J_j|), so
/// that the rank decision does not depend on the units of the parameters. With the SVD
/// Js = U S V^T and s_1 >= s_2 >= ..., the numerical rank is k = #{ s_i > rankTolerance * s_1 }.
/// V = [V_k V_N]: the columns V_N (n - k of them) span the numerical null space, the directions
/// (in scaled units) along which the residuals do not change.
///
/// Identifiability. Parameter j is identifiable when its scaled unit vector e_j is orthogonal to
/// the null space: its projection pi_j = |V_N^T e_j| (the norm of row j of V_N, between 0 and 1)
/// is below identifiabilityThreshold. Otherwise moving along a null direction changes p_j without
/// changing any residual, so the data do not determine p_j: it gets no standard deviation (NaN)
/// and is named in the combinations, however small its share in them.
///
/// Policy for what the data do not determine: the solution is the minimum-norm change from the
/// start values in scaled units: every step is -D V_k S_k^-1 U_k^T r, so p - p_start has no
/// component along V_N (the Levenberg-Marquardt result is projected the same way).
///
/// Covariance: C = s0^2 D V_k S_k^-2 V_k^T D with the a-posteriori variance factor
/// s0^2 = |r|^2 / (m - k) (so sigma scales with the observed scatter; with weights 1/sigma^2,
/// s0^2 is chi^2/dof and should be near 1). C is the covariance of every function of the
/// parameters the data determine (g^T p with g orthogonal to the null space in scaled units), e.g.
/// of each identifiable parameter and of predicted errors; for the others it has no meaning.

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
  /// All residuals, stacked like that. Override when a faster form exists (work shared by the
  /// observations, such as a reference point).
  virtual void residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const;
  /// Full Jacobian, stacked like residuals(). Override when a faster form exists.
  virtual void jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const;
};

/// Residual size statistics, unweighted, over observation blocks: the norm of the statistics
/// rows (rms, max) and each statistics row on its own (per axis: x, y, z).
struct ResidualStats {
  double rms = 0.0;
  double max = 0.0;
  int maxIndex = -1;
  Eigen::VectorXd rowRms;
  Eigen::VectorXd rowMax;
  std::vector<int> rowMaxIndex;
};
ResidualStats residualStats(const ResidualProblem& problem, const Eigen::VectorXd& p);

/// Builds ResidualStats from unweighted statistics rows one observation at a time (for sets
/// gathered from several problems, e.g. the held-out folds of a cross-validation).
class ResidualAccumulator {
 public:
  explicit ResidualAccumulator(int rows);
  /// `rows` unweighted residuals of observation `index`.
  void add(const double* residuals, int index);
  ResidualStats finish() const;

 private:
  ResidualStats stats_;
  double sum_ = 0.0;
  int count_ = 0;
};

/// Adds the observations of `problem` at parameters p (unweighted) with indices first, first+1...
void accumulateResiduals(const ResidualProblem& problem, const Eigen::VectorXd& p,
                         ResidualAccumulator& accumulator, int first = 0);

/// A direction in parameter space the data cannot see: residuals do not change along it.
/// The directions of a fit are a basis of the numerical null space in reduced row echelon form
/// (each has a pivot parameter with coefficient 1 that no other direction contains), so that
/// each is as sparse as the data allow.
struct Combination {
  /// Coefficients in scaled units (each parameter times its column norm), largest |value| = 1.
  /// Every parameter with a nonzero share is listed (none is dropped for being small).
  std::vector<std::pair<int, double>> terms;
  /// The same direction in internal units (mm, rad, ...), the pivot's coefficient being 1.
  std::vector<std::pair<int, double>> rawTerms;
  /// The pivot parameter (coefficient 1 in rawTerms).
  int pivot = -1;
  /// Relative singular value of the direction (s_i / s_1).
  double relativeSingularValue = 0.0;
  /// |J d| for the step d = rawTerms (one internal unit of the pivot): how much the weighted
  /// residuals change, root-sum-square over every row; no single residual changes by more.
  double residualChangePerPivotUnit = 0.0;
  /// In words (in units of the sensitivities; the report adds physical units).
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
  /// Standard deviation per parameter; NaN for parameters that are not identifiable.
  Eigen::VectorXd standardDeviation;
  /// Correlation; NaN in the rows and columns of parameters that are not identifiable.
  Eigen::MatrixXd correlation;
  /// Per parameter: the projection pi_j of its scaled unit vector onto the null space (0..1).
  Eigen::VectorXd nullSpaceProjection;
  /// The threshold on pi_j used for `identifiable`.
  double identifiabilityThreshold = 0.0;
  /// Per parameter: pi_j < identifiabilityThreshold.
  std::vector<bool> identifiable;
  /// In the order of their first parameter.
  std::vector<Combination> unidentifiable;
  /// D (the column scale), V_N (scaled null-space basis, n x (n - k)) and W = D V_k S_k^-1
  /// (n x k): a prediction with sensitivity row g (dprediction/dp) has the standard deviation
  /// s0 |g W|, and it is determined by the data when |g D V_N| is small against |g D|.
  Eigen::VectorXd columnScale;
  Eigen::MatrixXd nullBasis;
  Eigen::MatrixXd rangeFactor;
  /// rankTolerance * s_1: a change of the weighted residuals per scaled unit that the rank
  /// decision treats as none.
  double nullThreshold = 0.0;
};

/// How a prediction with sensitivity g = dprediction/dp (row vector, internal units) is known:
/// standard deviation s0 |g W|, and whether the data determine it at all.
struct PredictionUncertainty {
  double std = 0.0;  ///< NaN when not determined
  bool determined = true;
  /// |g D V_N| / |g D|: the share of the prediction along directions the data cannot see.
  double nullShare = 0.0;
};
/// For a quantity measured like the data (a predicted error in mm at a point: g is a row like
/// a measurement row of weight 1): determined when moving along the null space changes it by no
/// more than the rank decision neglects, |g D V_N| <= rankTolerance * s_1 (at every measured
/// point this holds by construction; at a tool or position the data do not cover it may not).
PredictionUncertainty predictionUncertainty(const FitStatistics& statistics,
                                            const Eigen::Ref<const Eigen::RowVectorXd>& g);
/// For a function of the parameters (a curve's value at a position, a difference of node
/// values): determined when its share along the null space is below the identifiability
/// threshold, as for a single parameter.
PredictionUncertainty functionUncertainty(const FitStatistics& statistics,
                                          const Eigen::Ref<const Eigen::RowVectorXd>& g);

/// Default threshold on the null-space projection pi_j. Rounding leaves projections of order
/// 1e-16 times the condition number of the retained part (below 1e-9 for the rank tolerance's
/// 1e7); a parameter with pi_j = 1e-6 changes by 1e-6 scaled units per unit along a direction
/// the data cannot see, which is already undetermined in principle.
inline constexpr double kIdentifiabilityThreshold = 1e-6;

enum class Method {
  /// Sensitivity matrix at the start values, factorised once; the exact residual is re-evaluated
  /// and the correction iterated with the same factorisation (for models linear in their
  /// parameters up to second-order terms, e.g. the 21-component model).
  Linear,
  /// Levenberg-Marquardt on the exact model: without a robust loss MINPACK's dense trust region
  /// (Moré's scaling and radius control), with one Ceres (a loss per observation block).
  LevenbergMarquardt,
};

enum class RobustLoss { None, Huber, Cauchy };

struct SolveOptions {
  Method method = Method::Linear;
  /// Relative singular-value threshold of the rank policy (scaled Jacobian).
  double rankTolerance = 1e-7;
  /// Threshold on a parameter's null-space projection above which it is not identifiable.
  double identifiabilityThreshold = kIdentifiabilityThreshold;
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
  /// Where the Jacobian behind `statistics` was taken: the start values for the linear method,
  /// the solution for Levenberg-Marquardt. Sensitivities of predictions are taken there too, so
  /// that they are judged against the same null space.
  Eigen::VectorXd linearisedAt;
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
                      const std::vector<std::string>& names, double rankTolerance,
                      double identifiabilityThreshold = kIdentifiabilityThreshold);

/// Solves the problem from `start` with options.method and fills every statistic.
FitResult solve(const ResidualProblem& problem, const Eigen::VectorXd& start,
                const SolveOptions& options = {});

/// Levenberg-Marquardt with Ceres (used by solve() when a robust loss is chosen). Returns the
/// parameters, iterations, convergence and termination text; statistics are filled by solve().
FitResult solveLevenbergMarquardt(const ResidualProblem& problem, const Eigen::VectorXd& start,
                                  const SolveOptions& options);

}  // namespace volcomp::calibration
