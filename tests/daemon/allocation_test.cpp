// The hot path does not allocate: every heap allocation on this thread is counted by a replaced
// global operator new while the loop steps through all its states, with fakes and with the real
// model (solveOffset on an example model file).

// GCC pairs the replaced operator delete (free) with operator new at inlined call sites and warns
// about a mismatch that is not one: our operator new allocates with malloc.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "loop_fixture.hpp"
#include "volcomp/daemon/compensation_model.hpp"

namespace {
std::atomic<long> allocations{0};
thread_local bool counting = false;
}  // namespace

void* operator new(std::size_t size) {
  if (counting) allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (counting) allocations.fetch_add(1, std::memory_order_relaxed);
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

namespace volcomp::daemon::testing {
namespace {

class Counting {
 public:
  Counting() {
    allocations = 0;
    counting = true;
  }
  ~Counting() { counting = false; }
  long count() const { return allocations.load(); }
};

TEST(NoAllocation, CountingOperatorNewSeesAllocations) {
  Counting c;
  auto* p = new std::string(100, 'x');  // the counter works at all
  const long n = c.count();
  delete p;
  EXPECT_GE(n, 1);
}

TEST_F(LoopTest, NoAllocationPerCycleInAnyState) {
  port.autoSequence = true;
  make();
  cycle();  // first connect and synchronisation outside the count is not needed, but harmless
  Counting c;
  for (int i = 0; i < 200; ++i) cycle();  // active
  port.sample.enable = false;
  for (int i = 0; i < 50; ++i) cycle();  // disabled
  port.sample.enable = true;
  port.sample.positionMm[0] = 1e6;
  for (int i = 0; i < 50; ++i) cycle();  // fault
  port.sample.positionMm[0] = 100.0;
  port.readError = std::make_error_code(std::errc::timed_out);
  for (int i = 0; i < 5; ++i) cycle();  // transaction fault
  port.readError = {};
  port.dropLink();
  for (int i = 0; i < 50; ++i) cycle();  // link lost, reconnect, resynchronise
  for (int i = 0; i < 50; ++i) cycle();
  loop->requestStop();
  for (int i = 0; i < 100 && !loop->finished(); ++i) cycle();  // stopping
  EXPECT_TRUE(loop->finished());
  EXPECT_EQ(c.count(), 0);
}

TEST(NoAllocation, RealModelOffsetSolveDoesNotAllocate) {
  const std::string file = std::string(VOLCOMP_EXAMPLES_DIR) + "/vmc-xyfz-21.json";
  std::shared_ptr<CompensationModel> model = loadCompensationModel(file);
  FakeClock clock;
  FakePort port;
  port.sample.positionMm = {400.0, 250.0, -200.0};
  CompensationLoop loop(port, clock, model, testSettings());
  clock.advance(std::chrono::milliseconds(10));
  loop.step();
  Counting c;
  for (int i = 0; i < 500; ++i) {
    port.sample.positionMm[0] += (i % 100 < 50) ? 0.5 : -0.5;  // both directions
    port.sample.positionMm[1] += 0.2;
    clock.advance(std::chrono::milliseconds(10));
    const CycleReport r = loop.step();
    ASSERT_EQ(r.state, LoopState::Active) << faultName(r.fault);
  }
  EXPECT_EQ(c.count(), 0);
  for (double o : port.last.offsetMm) EXPECT_TRUE(std::isfinite(o));
}

}  // namespace
}  // namespace volcomp::daemon::testing
