// Evaluation and the offset solve must never allocate: the global operator new is replaced by a
// counting one (which is why this is a separate executable), and the hot calls run with the
// counter armed.

// GCC pairs the replaced operator delete (free) with operator new at inlined call sites and warns
// about a mismatch that is not one: our operator new allocates with malloc.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
}  // namespace

void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace volcomp::model {
namespace {

class CountAllocations {
 public:
  CountAllocations() {
    g_allocations = 0;
    g_counting = true;
  }
  ~CountAllocations() { g_counting = false; }
  long count() const { return g_allocations.load(); }
};

TEST(Allocation, CounterWorks) {
  long seen = 0;
  {
    CountAllocations counter;
    auto* p = new std::vector<double>(10);
    seen = counter.count();
    delete p;
  }
  EXPECT_GE(seen, 2);
}

TEST(Allocation, EvaluateAndSolveNeverAllocate) {
  std::mt19937 rng(5);
  const MachineModel full(testing::fullModel("XYFZ"));
  const MachineModel random(testing::randomModel(rng, 1e-3, 500, 200));
  Workspace ws;
  volatile double sink = 0;
  long allocations = 0;
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
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
}

}  // namespace
}  // namespace volcomp::model
