// The loop's latch and saturation rules with the fake clock: sustained limiting (the clamp holding an axis:
// warning with the axis and the requested value, the SATURATED bit, then the fault
// sustained-limit with ramp-out) and the fault latch (a fault stays until the controller
// acknowledges it with its fault-ack input or by switching enable off).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

using namespace std::chrono_literals;

constexpr double kStep = 0.01;  // max rate 1 mm/s * 10 ms
constexpr double kEps = 1e-12;

bool has(std::uint16_t word, std::uint16_t bit) {
  return (word & bit) != 0;
}

class LatchSaturation : public LoopTest {
 protected:
  void SetUp() override {
    settings.saturationWarning = 200ms;
    settings.saturationFault = 500ms;
  }
};

// --- sustained limiting ----------------------------------------------------------------------

// The model asks for 0.8 mm on Y with a 0.5 mm band: after 200 ms of clamping the warning starts
// (once, naming Y and 0.8 mm) and SATURATED is set; after 500 ms the fault sustained-limit ramps
// the offsets out at max_rate.
TEST_F(LatchSaturation, ClampHeldLongerThanTheThresholdsWarnsThenFaults) {
  settings.faultLatch = false;
  model->setOffset({0.01, 0.8, 0.0});
  make();
  int warnings = 0;
  int firstSaturated = -1, firstFault = -1;
  for (int i = 1; i <= 60; ++i) {
    const CycleReport r = cycle();
    if (r.saturationAxis >= 0) {
      ++warnings;
      EXPECT_EQ(r.saturationAxis, 1);
      EXPECT_DOUBLE_EQ(r.saturationRequestedMm, 0.8);
    }
    if (firstSaturated < 0 && has(port.last.status, status::kSaturated)) firstSaturated = i;
    if (firstFault < 0 && r.fault == FaultCode::SustainedLimit) firstFault = i;
  }
  EXPECT_EQ(warnings, 1);
  // The clamp starts at the first cycle (t = 10 ms): 200 ms later is cycle 21, 500 ms cycle 51.
  EXPECT_EQ(firstSaturated, 21);
  EXPECT_EQ(firstFault, 51);
  EXPECT_EQ(faultCodeOf(port.last.status), FaultCode::SustainedLimit);
  EXPECT_TRUE(has(port.last.status, status::kSaturated));
  EXPECT_EQ(loop->counters().saturationWarnings, 1u);
  // Ramp-out in the fault: one step per cycle towards zero.
  const double y = port.last.offsetMm[1];
  cycle();
  EXPECT_NEAR(port.last.offsetMm[1], y - kStep, kEps);
  // The model back inside the band: the fault clears (no latch) and the offsets slew back in.
  model->setOffset({0.01, 0.3, 0.0});
  const CycleReport r = cycle();
  EXPECT_EQ(r.state, LoopState::Active);
  EXPECT_FALSE(has(port.last.status, status::kSaturated));
}

// The slew alone (ramping towards a target inside the band) is not saturation.
TEST_F(LatchSaturation, SlewingIsNotSaturation) {
  model->setOffset({0.0, 0.45, 0.0});  // 45 cycles of slewing
  make();
  for (int i = 0; i < 60; ++i) {
    const CycleReport r = cycle();
    EXPECT_LT(r.saturationAxis, 0);
    EXPECT_EQ(r.fault, FaultCode::None);
    EXPECT_FALSE(has(port.last.status, status::kSaturated));
  }
}

// A clamp that lets go before the threshold restarts the count.
TEST_F(LatchSaturation, InterruptedClampRestartsTheCount) {
  model->setOffset({0.0, 0.8, 0.0});
  make();
  for (int i = 0; i < 15; ++i) cycle();  // 150 ms
  model->setOffset({0.0, 0.4, 0.0});
  cycle();
  model->setOffset({0.0, 0.8, 0.0});
  for (int i = 0; i < 15; ++i) EXPECT_LT(cycle().saturationAxis, 0);
  EXPECT_FALSE(has(port.last.status, status::kSaturated));
}

TEST_F(LatchSaturation, ZeroThresholdsDisableTheStages) {
  settings.saturationWarning = 0ns;
  settings.saturationFault = 0ns;
  model->setOffset({0.0, 0.8, 0.0});
  make();
  for (int i = 0; i < 200; ++i) {
    const CycleReport r = cycle();
    EXPECT_EQ(r.fault, FaultCode::None);
    EXPECT_LT(r.saturationAxis, 0);
  }
}

// --- fault latch ---------------------------------------------------------------------------

// With the latch a fault stays after its cause is gone: the offsets keep ramping out, FAULT with
// the code of the latched fault and LATCHED are written, until the fault-ack input rises.
TEST_F(LatchSaturation, LatchedFaultStaysUntilTheAckBitRises) {
  port.autoSequence = true;
  port.sample.hasFaultAck = true;
  make();
  runUntilSettled();
  port.sample.positionMm[0] = 501.5;  // beyond travel + margin
  EXPECT_EQ(cycle().fault, FaultCode::OutOfTravel);
  port.sample.positionMm[0] = 100.0;  // the cause is gone ...
  for (int i = 0; i < 20; ++i) {
    const CycleReport r = cycle();  // ... but the fault stays
    EXPECT_EQ(r.state, LoopState::Fault);
    EXPECT_EQ(r.fault, FaultCode::OutOfTravel);
    EXPECT_TRUE(has(port.last.status, status::kLatched));
    EXPECT_EQ(faultCodeOf(port.last.status), FaultCode::OutOfTravel);
  }
  for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);  // ramped out
  EXPECT_EQ(loop->latchedFault(), FaultCode::OutOfTravel);
  port.sample.faultAck = true;  // the operator acknowledges on the HMI
  const CycleReport ack = cycle();
  EXPECT_TRUE(ack.acknowledged);
  EXPECT_EQ(ack.state, LoopState::Active);
  EXPECT_FALSE(has(port.last.status, status::kLatched));
  EXPECT_NEAR(port.last.offsetMm[2], kStep, kEps);  // slews back in
  // Held high, the ack bit acknowledges nothing more: a new fault latches again.
  port.sample.positionMm[0] = 501.5;
  cycle();
  port.sample.positionMm[0] = 100.0;
  EXPECT_EQ(cycle().state, LoopState::Fault);
}

// Without an ack input, switching enable off acknowledges (the enable toggle): the loop is then
// disabled, and active again when enable comes back.
TEST_F(LatchSaturation, EnableToggleAcknowledges) {
  make();
  runUntilSettled();
  model->setOffset({0.0, std::numeric_limits<double>::quiet_NaN(), 0.0});
  EXPECT_EQ(cycle().fault, FaultCode::ModelInvalid);
  model->setOffset({0.01, -0.02, 0.03});
  for (int i = 0; i < 5; ++i) EXPECT_EQ(cycle().state, LoopState::Fault);
  port.sample.enable = false;
  const CycleReport off = cycle();
  EXPECT_TRUE(off.acknowledged);
  EXPECT_EQ(off.state, LoopState::Disabled);
  port.sample.enable = true;
  EXPECT_EQ(cycle().state, LoopState::Active);
}

// A fault whose cause persists latches again at once after an acknowledge.
TEST_F(LatchSaturation, AcknowledgeWithTheCausePresentLatchesAgain) {
  port.sample.hasFaultAck = true;
  make();
  runUntilSettled();
  port.sample.positionMm[0] = 501.5;
  cycle();
  port.sample.faultAck = true;
  const CycleReport r = cycle();
  EXPECT_TRUE(r.acknowledged);
  EXPECT_EQ(r.fault, FaultCode::OutOfTravel);
  EXPECT_EQ(loop->latchedFault(), FaultCode::OutOfTravel);
}

// A failed transaction is a transport fault: never latched, it clears once the controller
// answers again.
TEST_F(LatchSaturation, TransactionFaultsAreNotLatched) {
  make();
  runUntilSettled();
  port.readError = std::make_error_code(std::errc::timed_out);
  EXPECT_EQ(cycle().fault, FaultCode::TransactionError);
  port.readError = {};
  EXPECT_EQ(cycle().state, LoopState::Active);
  EXPECT_EQ(loop->latchedFault(), FaultCode::None);
}

// Sustained limiting with the latch (the default): the fault stays after the model comes back
// inside the band, until acknowledged.
TEST_F(LatchSaturation, SustainedLimitIsLatchedByDefault) {
  port.sample.hasFaultAck = true;
  model->setOffset({0.0, 0.8, 0.0});
  make();
  for (int i = 0; i < 60; ++i) cycle();
  ASSERT_EQ(loop->fault(), FaultCode::SustainedLimit);
  model->setOffset({0.0, 0.3, 0.0});
  for (int i = 0; i < 60; ++i) EXPECT_EQ(cycle().fault, FaultCode::SustainedLimit);
  for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);
  port.sample.faultAck = true;
  EXPECT_EQ(cycle().state, LoopState::Active);
}

// A stop overrides a latched fault: ramp out, zero with status 0, finish.
TEST_F(LatchSaturation, StopWithALatchedFaultFinishes) {
  make();
  runUntilSettled();
  port.sample.positionMm[0] = 501.5;
  cycle();
  port.sample.positionMm[0] = 100.0;
  loop->requestStop();
  for (int i = 0; i < 20 && !loop->finished(); ++i) cycle();
  EXPECT_TRUE(loop->finished());
  EXPECT_EQ(port.last.status, 0);
}

}  // namespace
}  // namespace volcomp::loop::testing
