// Calibration timings (run pinned: taskset -c 1 bench_calibration).
// - Hanak, Zirn and Ruoff: the planar 2-DOF device, 7 parameters, 25 points, Levenberg-Marquardt
// from the
//   paper's starting values, with covariance and rank analysis. Target <= 1 ms, and no slower
//   than its anchor in the same run: Eigen's MINPACK port on the same residuals and Jacobian
//   with its covariance (planar_case.hpp).
// - A D-H chain (Bulla Ramos et al.'s Cartesian table), 4 deviations, 100 points,
// Levenberg-Marquardt
//   with covariance (dh_case.hpp).
// - 21 components of an XYFZ machine as 8-node tables (18 x 8 + 3 = 147 parameters), 5000
//   points (1000 positions x 5 tools), linear identification including covariance, correlation
//   and the naming of unidentifiable combinations. Target <= 0.1 s on one core.
// - The factorisation alone on that case's column-scaled 15000 x 147 sensitivity matrix, three
//   ways: Eigen's HouseholderQR (what the identification uses), ColPivHouseholderQR, and the
//   normal equations (J^T J by a rank update, then SelfAdjointEigenSolver), to choose between
//   them (docs/calibration.md).

#include <benchmark/benchmark.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "dh_case.hpp"
#include "planar_case.hpp"
#include "vmc_case.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/planar2dof.hpp"

namespace {

using namespace volcomp;
using namespace volcomp::calibration;
using nlohmann::json;

void BM_PlanarDeviceFit(benchmark::State& state) {
  const Planar2DofParameters start = bench::planarStart();
  const Planar2DofProblem problem({}, bench::planarData(), 0, kPaperFreeParameters, start);
  SolveOptions options;
  options.method = Method::LevenbergMarquardt;
  int rank = 0, iterations = 0;
  for (auto _ : state) {
    const FitResult fit = solve(problem, problem.freeVector(start), options);
    rank = fit.statistics.rank;
    iterations = fit.iterations;
    benchmark::DoNotOptimize(fit.parameters.data());
  }
  state.counters["rank"] = rank;
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_PlanarDeviceFit)->Unit(benchmark::kMicrosecond);

// The anchor: Eigen's MINPACK port on the same residuals and Jacobian, with its covariance.
void BM_PlanarDeviceFitAnchorEigenMinpack(benchmark::State& state) {
  const Planar2DofParameters start = bench::planarStart();
  const Planar2DofProblem problem({}, bench::planarData(), 0, kPaperFreeParameters, start);
  int iterations = 0, evaluations = 0;
  for (auto _ : state) {
    const bench::AnchorFit fit = bench::anchorFit(problem, problem.freeVector(start));
    iterations = fit.iterations;
    evaluations = fit.evaluations;
    benchmark::DoNotOptimize(fit.standardDeviation.data());
  }
  state.counters["iterations"] = iterations;
  state.counters["evaluations"] = evaluations;
}
BENCHMARK(BM_PlanarDeviceFitAnchorEigenMinpack)->Unit(benchmark::kMicrosecond);

void BM_DhChainFit(benchmark::State& state) {
  const auto& problem = *bench::dhCase().problem;
  SolveOptions options;
  options.method = Method::LevenbergMarquardt;
  int iterations = 0;
  for (auto _ : state) {
    const FitResult fit = solve(problem, problem.startVector(), options);
    iterations = fit.iterations;
    benchmark::DoNotOptimize(fit.statistics.covariance.data());
  }
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_DhChainFit)->Unit(benchmark::kMicrosecond);

void BM_TwentyOneComponentIdentification(benchmark::State& state) {
  const bench::VmcCase& c = bench::vmcCase();
  const auto problem = makeIdentificationProblem(c.document, c.data);
  int rank = 0;
  for (auto _ : state) {
    const FitResult fit = solve(*problem, problem->startVector());
    rank = fit.statistics.rank;
    benchmark::DoNotOptimize(fit.statistics.covariance.data());
  }
  state.counters["parameters"] = problem->parameterCount();
  state.counters["points"] = problem->observationCount();
  state.counters["rank"] = rank;
}
BENCHMARK(BM_TwentyOneComponentIdentification)->Unit(benchmark::kMillisecond)->MinTime(2.0);

const Eigen::MatrixXd& scaledJacobian() {
  static const Eigen::MatrixXd jacobian = [] {
    const bench::VmcCase& c = bench::vmcCase();
    const auto problem = makeIdentificationProblem(c.document, c.data);
    Eigen::MatrixXd j;
    problem->jacobian(problem->startVector(), j);
    for (Eigen::Index k = 0; k < j.cols(); ++k) {
      if (j.col(k).norm() > 0.0) j.col(k).normalize();
    }
    return j;
  }();
  return jacobian;
}

// Each iteration factorises a fresh copy (the copy is not timed).
template <typename Factorise>
void timeFactorisation(benchmark::State& state, Factorise factorise) {
  const Eigen::MatrixXd& j = scaledJacobian();
  Eigen::MatrixXd a(j.rows(), j.cols());
  for (auto _ : state) {
    state.PauseTiming();
    a = j;
    state.ResumeTiming();
    factorise(a);
    benchmark::ClobberMemory();
  }
  state.counters["rows"] = static_cast<double>(j.rows());
  state.counters["cols"] = static_cast<double>(j.cols());
}

void BM_QrEigenHouseholder(benchmark::State& state) {
  timeFactorisation(state, [&](Eigen::MatrixXd& a) {
    Eigen::HouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(a);
    benchmark::DoNotOptimize(qr.hCoeffs().data());
  });
}
BENCHMARK(BM_QrEigenHouseholder)->Unit(benchmark::kMillisecond);

void BM_QrEigenColPiv(benchmark::State& state) {
  timeFactorisation(state, [&](Eigen::MatrixXd& a) {
    Eigen::ColPivHouseholderQR<Eigen::Ref<Eigen::MatrixXd>> qr(a);
    benchmark::DoNotOptimize(qr.rank());
  });
}
BENCHMARK(BM_QrEigenColPiv)->Unit(benchmark::kMillisecond);

void BM_NormalEquationsEigen(benchmark::State& state) {
  timeFactorisation(state, [&](Eigen::MatrixXd& a) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(a.cols(), a.cols());
    normal.selfadjointView<Eigen::Lower>().rankUpdate(a.transpose());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normal.selfadjointView<Eigen::Lower>());
    benchmark::DoNotOptimize(eigen.eigenvalues().data());
  });
}
BENCHMARK(BM_NormalEquationsEigen)->Unit(benchmark::kMillisecond);

void BM_TwentyOneComponentProblemSetUp(benchmark::State& state) {
  const bench::VmcCase& c = bench::vmcCase();
  for (auto _ : state) {
    const auto problem = makeIdentificationProblem(c.document, c.data);
    benchmark::DoNotOptimize(problem.get());
  }
}
BENCHMARK(BM_TwentyOneComponentProblemSetUp)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
