// Levenberg-Marquardt on the exact model with Ceres: one residual block per observation (so that a
// robust loss acts per measured point), one block for the prior rows, all parameters in one block.

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include <ceres/ceres.h>

#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {
namespace {

class ObservationCost final : public ceres::CostFunction {
 public:
  ObservationCost(const ResidualProblem& problem, int observation)
      : problem_(problem), observation_(observation) {
    set_num_residuals(problem.residualsPerObservation());
    mutable_parameter_block_sizes()->push_back(problem.parameterCount());
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    problem_.observationResiduals(parameters[0], observation_, residuals);
    // A trial step can leave the model's domain (e.g. legs that no longer meet); returning false
    // makes Ceres reject the step and shrink the trust region instead of accepting NaN.
    for (int row = 0; row < num_residuals(); ++row) {
      if (!std::isfinite(residuals[row])) return false;
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      problem_.observationJacobian(parameters[0], observation_, jacobians[0]);
    }
    return true;
  }

 private:
  const ResidualProblem& problem_;
  int observation_;
};

class PriorCost final : public ceres::CostFunction {
 public:
  explicit PriorCost(const ResidualProblem& problem) : problem_(problem) {
    set_num_residuals(problem.priorRowCount());
    mutable_parameter_block_sizes()->push_back(problem.parameterCount());
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    problem_.priorResiduals(parameters[0], residuals);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      problem_.priorJacobian(parameters[0], jacobians[0]);
    }
    return true;
  }

 private:
  const ResidualProblem& problem_;
};

class ProgressCallback final : public ceres::IterationCallback {
 public:
  explicit ProgressCallback(const SolveOptions& options) : options_(options) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    std::ostringstream line;
    line << "iteration " << summary.iteration << ": cost " << summary.cost << ", step "
         << summary.step_norm;
    options_.progress(line.str());
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const SolveOptions& options_;
};

std::unique_ptr<ceres::LossFunction> makeLoss(const SolveOptions& options) {
  switch (options.loss) {
    case RobustLoss::Huber:
      return std::make_unique<ceres::HuberLoss>(options.lossScale);
    case RobustLoss::Cauchy:
      return std::make_unique<ceres::CauchyLoss>(options.lossScale);
    case RobustLoss::None:
      break;
  }
  return nullptr;
}

}  // namespace

FitResult solveLevenbergMarquardt(const ResidualProblem& problem, const Eigen::VectorXd& start,
                                  const SolveOptions& options) {
  FitResult result;
  result.start = start;
  result.parameters = start;
  const int n = problem.parameterCount();
  if (n == 0) {
    result.converged = true;
    result.termination = "no parameters to identify";
    return result;
  }
  const std::unique_ptr<ceres::LossFunction> loss = makeLoss(options);
  ceres::Problem::Options problemOptions;
  problemOptions.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceresProblem(problemOptions);
  for (int i = 0; i < problem.observationCount(); ++i) {
    ceresProblem.AddResidualBlock(new ObservationCost(problem, i), loss.get(),
                                  result.parameters.data());
  }
  if (problem.priorRowCount() > 0) {
    ceresProblem.AddResidualBlock(new PriorCost(problem), nullptr, result.parameters.data());
  }
  ceres::Solver::Options solverOptions;
  solverOptions.minimizer_type = ceres::TRUST_REGION;
  solverOptions.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solverOptions.linear_solver_type = ceres::DENSE_QR;
  solverOptions.max_num_iterations = options.maxIterations;
  solverOptions.function_tolerance = 1e-14;
  solverOptions.gradient_tolerance = 1e-16;
  solverOptions.parameter_tolerance = 1e-12;
  solverOptions.logging_type = ceres::SILENT;
  solverOptions.minimizer_progress_to_stdout = false;
  solverOptions.num_threads = 1;
  ProgressCallback callback(options);
  if (options.progress) solverOptions.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions, &ceresProblem, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.termination = summary.message;
  return result;
}

}  // namespace volcomp::calibration
