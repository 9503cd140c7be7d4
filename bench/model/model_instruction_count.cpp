// Fixed work for instruction counts (Google Benchmark's run length depends on time, so its
// instruction totals do not compare between runs): `sweeps` passes over the benchmark sweep of
// bench_model with one operation. Instructions per point, independent of the setup cost:
//   valgrind --tool=callgrind ./model_instruction_count exact 1   (total I1)
//   valgrind --tool=callgrind ./model_instruction_count exact 3   (total I3)
//   (I3 - I1) / (2 * 4096)
// Operations: exact, first (EvalMode::FirstOrder), offset (solveOffset), motion (evaluateMotion),
// batch and batchfirst (evaluateBatch over the sweep, Exact and FirstOrder), offsetbatch
// (solveOffsetBatch over the sweep).

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_fixture.hpp"
#include "volcomp/model/machine_model.hpp"

int main(int argc, char** argv) {
  using namespace volcomp::model;
  const std::string operation = argc > 1 ? argv[1] : "";
  const int sweeps = argc > 2 ? std::atoi(argv[2]) : 0;
  if ((operation != "exact" && operation != "first" && operation != "offset" &&
       operation != "motion" && operation != "batch" && operation != "batchfirst" &&
       operation != "offsetbatch") ||
      sweeps < 1) {
    std::fprintf(stderr,
                 "usage: model_instruction_count "
                 "exact|first|offset|motion|batch|batchfirst|offsetbatch SWEEPS\n");
    return 2;
  }
  const MachineModel model = bench::fullModel();
  const std::vector<Eigen::Vector3d> points = bench::sweep();
  Workspace ws;
  std::vector<PointError> out(points.size());
  std::vector<OffsetSolution> offsets(points.size());
  // Summed and printed so that no evaluation can be optimised away.
  double sum = 0.0;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    if (operation == "exact") {
      for (const auto& q : points) sum += evaluate(model, ws, q, {}, EvalMode::Exact).errorMm.x();
    } else if (operation == "first") {
      for (const auto& q : points) {
        sum += evaluate(model, ws, q, {}, EvalMode::FirstOrder).errorMm.x();
      }
    } else if (operation == "batch" || operation == "batchfirst") {
      evaluateBatch(model, ws, points, out,
                    operation == "batch" ? EvalMode::Exact : EvalMode::FirstOrder);
      for (const PointError& e : out) sum += e.errorMm.x();
    } else if (operation == "offsetbatch") {
      solveOffsetBatch(model, ws, points, offsets);
      for (const OffsetSolution& o : offsets) sum += o.offsetMm.x();
    } else if (operation == "offset") {
      for (const auto& q : points) sum += solveOffset(model, ws, q).offsetMm.x();
    } else {
      for (const auto& q : points) {
        evaluateMotion(model, q, {}, ws.motion);
        sum += ws.motion[3];
      }
    }
  }
  std::printf("%.17g\n", sum);
  return 0;
}
