// The hot path does not allocate: every heap allocation on this thread is counted by the shared
// allocation counter (malloc or the global operator new replaced) while the loop steps through
// all its states, with fakes and with the real
// model (solveOffset on an example model file).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "allocation_counter.hpp"
#include "loop_fixture.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/loop/compensation_model.hpp"

namespace volcomp::loop::testing {
namespace {

using Counting = volcomp::testutil::AllocationScope;

TEST(NoAllocation, CountingOperatorNewSeesAllocations) {
  Counting c;
  auto* p = new std::string(100, 'x');  // the counter works at all
  const std::uint64_t n = c.count();
  delete p;
  EXPECT_GE(n, 1U);
}

TEST_F(LoopTest, NoAllocationPerCycleInAnyState) {
  port.autoSequence = true;
  settings.latencyCompensation = true;  // its estimator included
  port.sample.hasTimestamp = true;      // and the controller clock's mapping
  port.sample.timestampTickS = 10e-6;
  make();
  cycle();  // first connect and synchronisation outside the count is not needed, but harmless
  Counting c;
  for (int i = 0; i < 200; ++i) {  // active
    port.sample.timestampTicks = static_cast<std::uint16_t>(port.sample.timestampTicks + 1000);
    cycle();
  }
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
  EXPECT_EQ(c.count(), 0U);
}

TEST(NoAllocation, RealModelOffsetSolveDoesNotAllocate) {
  const std::string file = std::string(VOLCOMP_EXAMPLES_DIR) + "/vmc-xyfz-21.json";
  config::ModelDocument document = config::loadModelFile(file);
  auto model = std::make_shared<MachineModelCompensation>(
      model::MachineModel(std::get<model::MachineModelSpec>(std::move(document.spec))), "vmc");
  FakeClock clock;
  FakePort port;
  port.sample.positionMm = {400.0, 250.0, -200.0};
  // With latency compensation: the estimator and the extrapolated evaluation on the hot path.
  for (const bool latency : {false, true}) {
    LoopSettings settings = testSettings();
    settings.latencyCompensation = latency;
    settings.controllerLatency = std::chrono::milliseconds(1);
    CompensationLoop loop(port, clock, model, settings);
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
    EXPECT_EQ(c.count(), 0U) << "latency compensation " << latency;
    if (latency) {
      EXPECT_GT(loop.counters().extrapolatedCycles, 400U);
    }
    for (double o : port.last.offsetMm) EXPECT_TRUE(std::isfinite(o));
    port.sample.positionMm = {400.0, 250.0, -200.0};
  }
}

}  // namespace
}  // namespace volcomp::loop::testing
