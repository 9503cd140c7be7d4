// Calibration timings (run pinned: taskset -c 1 bench_calibration).
// - Hanak, Zirn and Ruoff: the planar 2-DOF device, 7 parameters, 25 points, Levenberg-Marquardt from the
//   paper's starting values, with covariance and rank analysis. Target <= 1 ms.
// - 21 components of an XYFZ machine as 8-node tables (18 x 8 + 3 = 147 parameters), 5000
//   points (1000 positions x 5 tools), linear identification including covariance, correlation
//   and the naming of unidentifiable combinations. Target <= 0.1 s on one core.
// - The factorisation alone on that case's column-scaled 15000 x 147 sensitivity matrix, three
//   ways: Eigen's HouseholderQR (what the identification uses), ColPivHouseholderQR, and the
//   normal equations (J^T J by a rank update, then SelfAdjointEigenSolver), to choose between
//   them (docs/calibration.md).

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "vmc_case.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/planar2dof.hpp"

namespace {

using namespace volcomp;
using namespace volcomp::calibration;
using nlohmann::json;

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<Planar2DofSample> planarData() {
  const Planar2DofParameters truth{0.30, 0.10,          1.53,    0.13,  0.0,
                                   0.0,  -0.184 * kDeg, -2.1e-3, 0.7e-3};
  std::mt19937 generator(3);
  std::normal_distribution<double> noise(0.0, 1.8e-3);
  const double c = std::cos(truth[phi]), s = std::sin(truth[phi]);
  std::vector<Planar2DofSample> samples;
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      const Eigen::Vector2d tcp(-20.0 + 10.0 * column, 180.0 + 10.0 * row);
      const Eigen::Vector2d readings = planar2DofInverse({}, truth, tcp);
      Planar2DofSample sample{
          readings.x(), readings.y(),
          Eigen::Vector2d(c * tcp.x() + s * tcp.y(), -s * tcp.x() + c * tcp.y())};
      if (row + column > 0) {
        const double dy = noise(generator);  // drawn in this order whatever the compiler
        sample.lgpMm += Eigen::Vector2d(noise(generator), dy);
      }
      samples.push_back(sample);
    }
  }
  samples[0].lgpMm -= Eigen::Vector2d(truth[exK], truth[eyK]);
  return samples;
}

void BM_PlanarDeviceFit(benchmark::State& state) {
  const Planar2DofParameters start{0.1, 0.1, 1.0, 0.1, 0.0, 0.0, 0.057 * kDeg, 3e-3, 3e-3};
  const Planar2DofProblem problem({}, planarData(), 0, kPaperFreeParameters, start);
  SolveOptions options;
  options.method = Method::LevenbergMarquardt;
  int rank = 0;
  for (auto _ : state) {
    const FitResult fit = solve(problem, problem.freeVector(start), options);
    rank = fit.statistics.rank;
    benchmark::DoNotOptimize(fit.parameters.data());
  }
  state.counters["rank"] = rank;
}
BENCHMARK(BM_PlanarDeviceFit)->Unit(benchmark::kMicrosecond);

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
