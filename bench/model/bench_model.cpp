// ns/point for a full 21-component XYFZ model (18 motion errors as 101-point uniform tables,
// linear and cubic mixed, plus EC0Y, EB0Z, EA0Z squareness) over a sweep of points through the
// working volume. Run pinned:
//   taskset -c 1 ./bench_model --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "volcomp/model/machine_model.hpp"

namespace {

using namespace volcomp::model;

constexpr int kNodes = 101;
constexpr int kPoints = 4096;

TableSpec smoothTable(double lo, double hi, double amplitude, double phase, Interpolation kind) {
  TableSpec table;
  table.interpolation = kind;
  for (int i = 0; i < kNodes; ++i) {
    const double x = lo + (hi - lo) * i / (kNodes - 1);
    table.positionsMm.push_back(x);
    table.values.push_back(amplitude * std::sin(phase + 3.0 * (x - lo) / (hi - lo)));
  }
  return table;
}

MachineModel fullModel() {
  MachineModelSpec spec;
  spec.topology = "XYFZ";
  const std::array<std::array<double, 2>, 3> travel = {{{0, 850}, {0, 500}, {-500, 0}}};
  for (int k = 0; k < 3; ++k) spec.travelMm[k] = travel[k];
  spec.toolMm = Eigen::Vector3d(0, 0, 120);
  for (int k = 0; k < 3; ++k) {
    for (int kind = 0; kind < 6; ++kind) {
      const double amplitude = kind < 3 ? 0.02 : 5e-5;
      const Interpolation interpolation =
          (kind % 2 == 0) ? Interpolation::Linear : Interpolation::Cubic;
      spec.motion[k * 6 + kind] =
          smoothTable(travel[k][0], travel[k][1], amplitude, 0.3 * kind + k, interpolation);
    }
  }
  spec.locationRad[locationIndex(Axis::Y, 2)] = 18.5e-6;
  spec.locationRad[locationIndex(Axis::Z, 1)] = -12.0e-6;
  spec.locationRad[locationIndex(Axis::Z, 0)] = 7.0e-6;
  return MachineModel(spec);
}

// A sweep along a diagonal-ish path through the volume (consecutive points close together, as in
// a live loop), covering every table interval.
std::vector<Eigen::Vector3d> sweep() {
  std::vector<Eigen::Vector3d> points;
  points.reserve(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    const double s = static_cast<double>(i) / (kPoints - 1);
    points.emplace_back(850 * s, 250 + 240 * std::sin(6.283 * s), -500 * (1 - s) * s * 4);
  }
  return points;
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
  state.SetItemsProcessed(state.iterations() * kPoints);
  state.counters["ns_per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kPoints),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_EvaluateExact(benchmark::State& state) {
  BM_Evaluate(state, EvalMode::Exact);
}
void BM_EvaluateFirstOrder(benchmark::State& state) {
  BM_Evaluate(state, EvalMode::FirstOrder);
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
  state.SetItemsProcessed(state.iterations() * kPoints);
  state.counters["ns_per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kPoints),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["iterations_per_point"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations() * kPoints);
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
  state.counters["ns_per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations() * kPoints),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_EvaluateExact);
BENCHMARK(BM_EvaluateFirstOrder);
BENCHMARK(BM_SolveOffset);
BENCHMARK(BM_EvaluateMotionOnly);

}  // namespace

BENCHMARK_MAIN();
