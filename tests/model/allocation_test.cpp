// Evaluation and the offset solve must never allocate: the shared allocation counter (which
// replaces malloc or the global operator new, hence a separate executable) counts this thread's
// allocations while the hot calls run.

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "allocation_counter.hpp"
#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

using CountAllocations = volcomp::testutil::AllocationScope;

// Where the vector of CounterWorks goes: a volatile store, so that the compiler cannot elide
// the allocation (Clang removes a new/delete pair whose result is not used otherwise).
std::vector<double>* volatile g_allocated = nullptr;

TEST(Allocation, CounterWorks) {
  std::uint64_t seen = 0;
  {
    CountAllocations counter;
    g_allocated = new std::vector<double>(10);
    seen = counter.count();
    delete g_allocated;
  }
  EXPECT_GE(seen, 2U);
}

TEST(Allocation, EvaluateAndSolveNeverAllocate) {
  std::mt19937 rng(5);
  const MachineModel full(testing::fullModel("XYFZ"));
  const MachineModel random(testing::randomModel(rng, 1e-3, 500, 200));
  Workspace ws;
  volatile double sink = 0;
  std::uint64_t allocations = 0;
  // evaluateBatch's input and output, allocated before counting; 11 points: two full blocks of
  // four and a padded one of three.
  std::vector<Eigen::Vector3d> points;
  std::vector<Directions> directions;
  for (int i = 0; i < 11; ++i) {
    points.emplace_back(40.0 * i, 300 - 20.0 * i, -15.0 * i);
    directions.push_back({Direction::Positive, Direction::Negative, Direction::Unknown});
  }
  std::vector<PointError> out(points.size());
  std::vector<OffsetSolution> offsets(points.size());
  {
    CountAllocations counter;
    for (const MachineModel* model : {&full, &random}) {
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d q(4.0 * i, 300 - 2.0 * i, -1.5 * i);
        const Directions dirs = {Direction::Positive, Direction::Negative, Direction::Unknown};
        for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
          sink = sink + evaluate(*model, ws, q, dirs, mode).errorMm.x();
          sink = sink + evaluate(*model, ws, q, Eigen::Vector3d(1, 2, 3), dirs, mode).errorMm.y();
          OffsetOptions options;
          options.mode = mode;
          sink = sink + solveOffset(*model, ws, q, dirs, options).offsetMm.z();
        }
        MotionValues values{};
        sink = sink + evaluateMotion(*model, q, dirs, values);
        sink = sink + composeError(*model, ws, q, values, model->toolMm()).errorMm.z();
        sink = sink + model->motion(3).value(q.x(), Direction::Negative);
        for (const Grid& grid : model->grids()) sink = sink + grid.valueMm(q.data());
      }
      for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
        evaluateBatch(*model, ws, points, out, mode);
        evaluateBatch(*model, ws, points, out, mode, directions);
        sink = sink + out.back().errorMm.x();
      }
      solveOffsetBatch(*model, ws, points, offsets);
      solveOffsetBatch(*model, ws, points, offsets, directions);
      sink = sink + offsets.back().offsetMm.x();
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0U);
}

}  // namespace
}  // namespace volcomp::model
