// ns/point for a full 21-component XYFZ model (18 motion errors as 101-point uniform tables,
// linear and cubic mixed, plus EC0Y, EB0Z, EA0Z squareness) over a sweep of points through the
// working volume. Run pinned:
//   taskset -c 1 ./bench_model --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <vector>

#include <benchmark/benchmark.h>

#include "bench_fixture.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {

using namespace volcomp::model;

using bench::fullModel;
using bench::kPoints;
using bench::sweep;

// The sweep's points: items processed, and `ns_per_point` (CPU time).
void countPoints(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations() * kPoints);
  state.counters["ns_per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kPoints),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_Evaluate(benchmark::State& state, EvalMode mode) {
  const MachineModel model = fullModel();
  const std::vector<Eigen::Vector3d> points = sweep();
  Workspace ws;
  for (auto _ : state) {
    for (const Eigen::Vector3d& q : points) {
      PointError e = evaluate(model, ws, q, {}, mode);
      benchmark::DoNotOptimize(e);
    }
  }
  countPoints(state);
}

void BM_EvaluateExact(benchmark::State& state) {
  BM_Evaluate(state, EvalMode::Exact);
}
void BM_EvaluateFirstOrder(benchmark::State& state) {
  BM_Evaluate(state, EvalMode::FirstOrder);
}

// The whole sweep through evaluateBatch: four points per SIMD register.
void BM_EvaluateBatch(benchmark::State& state, EvalMode mode) {
  const MachineModel model = fullModel();
  const std::vector<Eigen::Vector3d> points = sweep();
  std::vector<PointError> out(points.size());
  Workspace ws;
  for (auto _ : state) {
    evaluateBatch(model, ws, points, out, mode);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  countPoints(state);
}

void BM_EvaluateBatchExact(benchmark::State& state) {
  BM_EvaluateBatch(state, EvalMode::Exact);
}
void BM_EvaluateBatchFirstOrder(benchmark::State& state) {
  BM_EvaluateBatch(state, EvalMode::FirstOrder);
}

void BM_SolveOffset(benchmark::State& state) {
  const MachineModel model = fullModel();
  const std::vector<Eigen::Vector3d> points = sweep();
  Workspace ws;
  long iterations = 0;
  for (auto _ : state) {
    for (const Eigen::Vector3d& q : points) {
      OffsetSolution o = solveOffset(model, ws, q);
      iterations += o.iterations;
      benchmark::DoNotOptimize(o);
    }
  }
  countPoints(state);
  state.counters["iterations_per_point"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations() * kPoints);
}

// The whole sweep through solveOffsetBatch: four points per SIMD register, each lane iterating
// until its own residual is below 1e-9 mm.
void BM_SolveOffsetBatch(benchmark::State& state) {
  const MachineModel model = fullModel();
  const std::vector<Eigen::Vector3d> points = sweep();
  std::vector<OffsetSolution> out(points.size());
  Workspace ws;
  for (auto _ : state) {
    solveOffsetBatch(model, ws, points, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  countPoints(state);
}

void BM_EvaluateMotionOnly(benchmark::State& state) {
  const MachineModel model = fullModel();
  const std::vector<Eigen::Vector3d> points = sweep();
  MotionValues values{};
  for (auto _ : state) {
    for (const Eigen::Vector3d& q : points) {
      benchmark::DoNotOptimize(evaluateMotion(model, q, {}, values));
      benchmark::DoNotOptimize(values);
    }
  }
  countPoints(state);
}

BENCHMARK(BM_EvaluateExact);
BENCHMARK(BM_EvaluateFirstOrder);
BENCHMARK(BM_EvaluateBatchExact);
BENCHMARK(BM_EvaluateBatchFirstOrder);
BENCHMARK(BM_SolveOffset);
BENCHMARK(BM_SolveOffsetBatch);
BENCHMARK(BM_EvaluateMotionOnly);

}  // namespace

BENCHMARK_MAIN();
