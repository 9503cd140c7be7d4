// One test (or a few) per safety rule of daemon.md, driving the loop with fakes and a fake clock.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

constexpr double kStep = 0.01;  // max rate 1 mm/s * 10 ms
constexpr double kEps = 1e-12;

bool has(std::uint16_t word, std::uint16_t bit) {
  return (word & bit) != 0;
}

// --- starting ------------------------------------------------------------------------------

TEST_F(LoopTest, StartingWritesNothingUntilAppliedOffsetsAreReadBack) {
  port.readback = false;  // the driver has not delivered the applied offsets yet
  make();
  for (int i = 0; i < 20; ++i) EXPECT_EQ(cycle().state, LoopState::Starting);
  EXPECT_EQ(port.writeCalls, 0);

  port.readback = true;
  port.applied = {0.2, -0.1, 0.0};  // what the controller currently applies
  const CycleReport r = cycle();
  ASSERT_TRUE(r.wrote);
  // Continues from the read-back: one rate-limited step towards the model, no jump.
  EXPECT_NEAR(port.last.offsetMm[0], 0.2 - kStep, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], -0.1 + kStep, kEps);
  EXPECT_NEAR(port.last.offsetMm[2], kStep, kEps);
  EXPECT_EQ(r.state, LoopState::Active);
}

TEST_F(LoopTest, WithoutReadBackStartingWaitsUntilOffsetsAreKnownZero) {
  port.readback = false;
  settings.offsetReadback = false;
  settings.plcZeroAfter = std::chrono::milliseconds(200);
  make();
  for (int i = 0; i < 19; ++i) cycle();  // 190 ms: the PLC may still hold offsets
  EXPECT_EQ(port.writeCalls, 0);
  cycle();  // 200 ms without a heartbeat from us: the PLC has zeroed them
  ASSERT_EQ(port.writes, 1);
  EXPECT_NEAR(port.last.offsetMm[0], kStep, kEps);  // ramping up from zero
}

TEST_F(LoopTest, NanReadBackKeepsStartingWithAFault) {
  port.applied = {std::numeric_limits<double>::quiet_NaN(), 0, 0};
  make();
  const CycleReport r = cycle();
  EXPECT_EQ(r.state, LoopState::Starting);
  EXPECT_EQ(r.fault, FaultCode::InvalidInput);
  EXPECT_EQ(port.writeCalls, 0);
}

// --- active ----------------------------------------------------------------------------------

TEST_F(LoopTest, ActiveWritesModelOffsetsThroughTheLimiter) {
  make();
  const CycleReport first = cycle();
  EXPECT_EQ(first.state, LoopState::Active);
  EXPECT_TRUE(has(port.last.status, status::kActive));
  // Model offset (0.01, -0.02, 0.03) from zero: the first cycle moves each axis by at most 0.01.
  EXPECT_NEAR(port.last.offsetMm[0], 0.01, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], -0.01, kEps);
  EXPECT_NEAR(port.last.offsetMm[2], 0.01, kEps);
  EXPECT_TRUE(has(port.last.status, status::kLimited));
  runUntilSettled();
  EXPECT_DOUBLE_EQ(port.last.offsetMm[0], 0.01);
  EXPECT_DOUBLE_EQ(port.last.offsetMm[1], -0.02);
  EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  EXPECT_EQ(port.last.status, status::kActive);
}

TEST_F(LoopTest, ModelTargetBeyondMaxOffsetIsClampedAndFlaggedLimited) {
  model->setOffset({0.9, 0.0, 0.0});
  make();
  for (int i = 0; i < 100; ++i) cycle();
  EXPECT_DOUBLE_EQ(port.last.offsetMm[0], 0.5);
  EXPECT_TRUE(has(port.last.status, status::kLimited));
  EXPECT_TRUE(has(port.last.status, status::kActive));
}

TEST_F(LoopTest, HeartbeatIncrementsEveryCycle) {
  make();
  std::uint16_t previous = 0;
  for (int i = 0; i < 5; ++i) {
    cycle();
    EXPECT_EQ(port.last.heartbeat, static_cast<std::uint16_t>(previous + 1));
    previous = port.last.heartbeat;
  }
  model->setOffset({0, 0, 0});
  port.sample.enable = false;  // also in the other states
  cycle();
  EXPECT_EQ(port.last.heartbeat, static_cast<std::uint16_t>(previous + 1));
}

TEST_F(LoopTest, DirectionsOfMotionReachTheModel) {
  make();
  cycle();
  port.sample.positionMm[0] += 1.0;
  port.sample.positionMm[1] -= 1.0;
  cycle();
  EXPECT_EQ(model->lastDirections[0], model::Direction::Positive);
  EXPECT_EQ(model->lastDirections[1], model::Direction::Negative);
  EXPECT_EQ(model->lastDirections[2], model::Direction::Unknown);
}

// --- disabled --------------------------------------------------------------------------------

TEST_F(LoopTest, DisabledRampsToZeroAtMaxRateThenWritesZero) {
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  port.sample.enable = false;
  std::vector<double> z;
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(cycle().state, LoopState::Disabled);
    EXPECT_TRUE(has(port.last.status, status::kDisabled));
    EXPECT_FALSE(has(port.last.status, status::kActive));
    z.push_back(port.last.offsetMm[2]);
  }
  // 0.03 -> 0.02 -> 0.01 -> 0 then zero.
  EXPECT_NEAR(z[0], 0.02, kEps);
  EXPECT_NEAR(z[1], 0.01, kEps);
  for (std::size_t i = 2; i < z.size(); ++i) EXPECT_EQ(z[i], 0.0);
  EXPECT_EQ(port.last.offsetMm[0], 0.0);
  EXPECT_EQ(port.last.offsetMm[1], 0.0);
}

// A controller that ignores offset changes while disabled (LinuxCNC with the machine off or not
// homed) still applies the old offsets when enable comes back, although this loop ramped them to
// zero meanwhile: compensation resumes from the read-back, one step from what is applied.
TEST_F(LoopTest, ResumingAfterDisabledContinuesFromTheReadBack) {
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  port.holdApplied = true;  // the ramp below is written but never applied
  port.sample.homed = false;
  for (int i = 0; i < 6; ++i) cycle();
  ASSERT_EQ(port.last.offsetMm[2], 0.0);
  ASSERT_DOUBLE_EQ(port.applied[2], 0.03);
  port.holdApplied = false;
  port.sample.homed = true;
  model->setOffset({0.01, -0.02, 0.0});
  const CycleReport r = cycle();
  EXPECT_EQ(r.state, LoopState::Active);
  // From the applied (0.01, -0.02, 0.03) towards (0.01, -0.02, 0): one step, not a jump from 0.
  EXPECT_NEAR(port.last.offsetMm[0], 0.01, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], -0.02, kEps);
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 - kStep, kEps);
  EXPECT_EQ(loop->counters().resynchronisations, 1u);
}

// A controller that applies the ramp while disabled agrees with the loop when enable returns:
// nothing re-seeds.
TEST_F(LoopTest, ResumingWithAnAgreeingReadBackKeepsTheLimiterState) {
  make();
  runUntilSettled();
  port.sample.enable = false;
  for (int i = 0; i < 6; ++i) cycle();
  port.sample.enable = true;
  cycle();
  EXPECT_NEAR(port.last.offsetMm[2], kStep, kEps);
  EXPECT_EQ(loop->counters().resynchronisations, 0u);
}

TEST_F(LoopTest, NotHomedWritesOnlyZero) {
  port.sample.homed = false;
  port.sample.positionMm = {9999.0, -9999.0, 12345.0};  // unhomed: meaningless positions
  make();
  for (int i = 0; i < 20; ++i) {
    const CycleReport r = cycle();
    EXPECT_EQ(r.state, LoopState::Disabled);
    EXPECT_EQ(r.fault, FaultCode::None);
    for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);
    EXPECT_TRUE(has(port.last.status, status::kDisabled));
  }
  EXPECT_EQ(model->calls, 0);
}

// --- fault -----------------------------------------------------------------------------------

TEST_F(LoopTest, FrozenLifeCounterIsStaleInputFault) {
  port.autoSequence = true;
  settings.faultLatch = false;  // the fault clears with its cause
  make();
  runUntilSettled();
  ASSERT_EQ(loop->state(), LoopState::Active);
  port.autoSequence = false;  // the PLC stops updating; the counter keeps its last value
  port.sample.hasSequence = true;
  port.sample.sequence = port.sequence;
  for (int i = 0; i < 10; ++i) EXPECT_EQ(cycle().state, LoopState::Active) << i;  // 100 ms
  const CycleReport r = cycle();  // 110 ms > stale timeout
  EXPECT_EQ(r.state, LoopState::Fault);
  EXPECT_EQ(r.fault, FaultCode::StaleInput);
  EXPECT_TRUE(has(port.last.status, status::kFault));
  EXPECT_EQ(faultCodeOf(port.last.status), FaultCode::StaleInput);
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 - kStep, kEps);  // ramping to zero
  port.autoSequence = true;                                // the counter moves again
  EXPECT_EQ(cycle().state, LoopState::Active);
}

TEST_F(LoopTest, FrozenPositionsAreStaleWhenConfigured) {
  settings.frozenPositionsAreStale = true;
  settings.faultLatch = false;  // the fault clears with its cause
  make();
  // Positions last changed at the first cycle; 100 ms later they are exactly at the timeout,
  // not beyond it.
  for (int i = 0; i < 11; ++i) EXPECT_EQ(cycle().state, LoopState::Active);
  EXPECT_EQ(cycle().fault, FaultCode::StaleInput);
  port.sample.positionMm[0] += 0.001;
  EXPECT_EQ(cycle().state, LoopState::Active);
}

TEST_F(LoopTest, FrozenPositionsAloneAreNotStaleByDefault) {
  // A machine at rest reports the same commanded position for ever; removing the offsets then
  // would move the axes for no reason.
  make();
  for (int i = 0; i < 100; ++i) EXPECT_EQ(cycle().state, LoopState::Active);
}

TEST_F(LoopTest, PositionBeyondTravelMarginFaults) {
  make();
  runUntilSettled();
  port.sample.positionMm[0] = 501.5;  // travel [0, 500], margin 1 mm
  const CycleReport r = cycle();
  EXPECT_EQ(r.state, LoopState::Fault);
  EXPECT_EQ(r.fault, FaultCode::OutOfTravel);
  EXPECT_EQ(faultCodeOf(port.last.status), FaultCode::OutOfTravel);
  EXPECT_TRUE(has(port.last.status, status::kOutOfTravel));
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 - kStep, kEps);
}

TEST_F(LoopTest, PositionOutsideTravelWithinMarginOnlyFlags) {
  port.sample.positionMm[2] = 0.5;  // travel [-300, 0], margin 1 mm
  make();
  const CycleReport r = cycle();
  EXPECT_EQ(r.state, LoopState::Active);
  EXPECT_TRUE(has(port.last.status, status::kOutOfTravel));
  EXPECT_TRUE(has(port.last.status, status::kActive));
}

TEST_F(LoopTest, NanPositionIsAFaultNotAnOutput) {
  settings.faultLatch = false;  // the fault clears with its cause
  make();
  runUntilSettled();
  port.sample.positionMm[1] = std::numeric_limits<double>::quiet_NaN();
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::InvalidInput);
  for (double o : port.last.offsetMm) EXPECT_TRUE(std::isfinite(o));
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 - kStep, kEps);
  port.sample.positionMm[1] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(cycle().fault, FaultCode::InvalidInput);
  port.sample.positionMm[1] = 50.0;
  EXPECT_EQ(cycle().state, LoopState::Active);
}

TEST_F(LoopTest, NanAppliedOffsetIsAFault) {
  make();
  cycle();
  port.holdApplied = true;
  port.applied[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(cycle().fault, FaultCode::InvalidInput);
}

TEST_F(LoopTest, NanFromTheModelIsAFault) {
  make();
  runUntilSettled();
  model->setOffset({0.0, std::numeric_limits<double>::quiet_NaN(), 0.0});
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::ModelInvalid);
  for (double o : port.last.offsetMm) EXPECT_TRUE(std::isfinite(o));
}

TEST_F(LoopTest, UnconvergedOffsetSolveIsAFault) {
  make();
  model->converged = false;
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::NotConverged);
  for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);
}

TEST_F(LoopTest, FailedReadOnALiveLinkIsATransactionFault) {
  make();
  runUntilSettled();
  port.readError = std::make_error_code(std::errc::timed_out);
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::TransactionError);
  EXPECT_TRUE(port.connected());  // not a link loss
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 - kStep, kEps);
  port.readError = {};
  EXPECT_EQ(cycle().state, LoopState::Active);
  EXPECT_EQ(loop->counters().readErrors, 1u);
}

// A timed-out write may or may not have been applied (a late answer, a lost reply): the next value
// written is within one step of both what was acknowledged (0.01) and what was attempted (0.02).
TEST_F(LoopTest, FailedWriteKeepsTheNextWithinOneStepOfAcknowledgedAndAttempted) {
  make();
  cycle();
  ASSERT_NEAR(port.last.offsetMm[2], 0.01, kEps);
  port.writeError = std::make_error_code(std::errc::timed_out);
  const CycleReport failed = cycle();  // 0.02 attempted; the controller may have applied it
  EXPECT_TRUE(failed.unknownOutcome);
  port.writeError = {};
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::TransactionError);
  // Ramping down in the fault: from 0.02 one step is 0.01, which is also within one step of
  // 0.01; stepping down from 0.01 to 0 would be two steps from 0.02.
  EXPECT_NEAR(port.last.offsetMm[2], 0.01, kEps);
  EXPECT_EQ(loop->counters().writeErrors, 1u);
  EXPECT_EQ(loop->counters().unknownOutcomes, 1u);
  cycle();  // acknowledged: the controller has 0.01 for sure, the ramp goes on from there
  EXPECT_NEAR(port.last.offsetMm[2], 0.02, kEps);  // the fault cleared: towards the model again
}

// The daemon was stopped or blocked with the link up (SIGSTOP, a stuck transaction) and the PLC's
// heartbeat watchdog ramped the applied offsets out meanwhile: the next write continues from what
// is applied (one step from it), not from what this loop last wrote.
TEST_F(LoopTest, AppliedOffsetsChangedByThePlcAreFollowedWithoutAJump) {
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  clock.advance(std::chrono::milliseconds(400));  // the daemon was stopped (SIGSTOP) ...
  port.applied = {0.0, 0.0, 0.0};                 // ... and the PLC's watchdog zeroed them
  const CycleReport r = cycle();
  ASSERT_TRUE(r.wrote);
  // From 0 applied, towards the model's (0.01, -0.02, 0.03): one step of 0.01 at most.
  EXPECT_NEAR(port.last.offsetMm[0], kStep, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], -kStep, kEps);
  EXPECT_NEAR(port.last.offsetMm[2], kStep, kEps);
  EXPECT_EQ(loop->counters().resynchronisations, 1u);
}

// A read-back within one step of what was written (rounding, lag) does not re-seed the limiter,
// even after a silence.
TEST_F(LoopTest, ReadBackWithinOneStepKeepsTheLimiterState) {
  make();
  runUntilSettled();
  port.holdApplied = true;
  port.applied = {0.01, -0.02, 0.03 - 0.5 * kStep};
  clock.advance(std::chrono::milliseconds(400));
  cycle();
  EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  EXPECT_EQ(loop->counters().resynchronisations, 0u);
}

// While the loop writes every cycle, a read-back that disagrees is stale registers (a frozen
// controller), not the PLC acting: following it would make the writes jump. Nothing re-seeds.
TEST_F(LoopTest, DisagreeingReadBackWhileWritingEveryCycleIsNotFollowed) {
  make();
  runUntilSettled();
  port.holdApplied = true;
  port.applied = {0.0, 0.0, 0.0};
  for (int i = 0; i < 5; ++i) {
    cycle();
    EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  }
  EXPECT_EQ(loop->counters().resynchronisations, 0u);
}

// After a silence, a life counter that has not moved marks the read-back as old: not followed.
TEST_F(LoopTest, ReadBackWithAFrozenLifeCounterIsNotFollowed) {
  port.autoSequence = true;
  make();
  runUntilSettled();
  port.autoSequence = false;  // the PLC's counter stops: its registers are not refreshed
  port.sample.hasSequence = true;
  port.sample.sequence = port.sequence;
  port.holdApplied = true;
  port.applied = {0.0, 0.0, 0.0};
  clock.advance(std::chrono::milliseconds(40));
  cycle();
  EXPECT_EQ(loop->counters().resynchronisations, 0u);
}

// Without a read-back, a loop that has not written for plcZeroAfter knows the PLC has zeroed the
// offsets and ramps up from zero.
TEST_F(LoopTest, WithoutReadBackALongSilenceRestartsFromZero) {
  port.readback = false;
  settings.offsetReadback = false;
  settings.plcZeroAfter = std::chrono::milliseconds(200);
  make();
  for (int i = 0; i < 20; ++i) cycle();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  clock.advance(std::chrono::milliseconds(500));  // the process was stopped for half a second
  cycle();
  EXPECT_NEAR(port.last.offsetMm[2], kStep, kEps);
  EXPECT_EQ(loop->counters().resynchronisations, 1u);
}

// --- link lost -------------------------------------------------------------------------------

TEST_F(LoopTest, LinkLossReconnectsWithBoundedBackoffAndContinuesFromReadBack) {
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  const int writesBefore = port.writes;

  port.dropLink();
  port.connectError = std::make_error_code(std::errc::connection_refused);
  const auto t0 = clock.now();
  EXPECT_EQ(cycle().state, LoopState::LinkLost);
  std::vector<long> attemptsMs;
  int lastCalls = port.connectCalls;
  for (int i = 0; i < 1200; ++i) {  // 12 s
    EXPECT_EQ(cycle().state, LoopState::LinkLost);
    if (port.connectCalls != lastCalls) {
      lastCalls = port.connectCalls;
      attemptsMs.push_back(static_cast<long>(
          std::chrono::duration_cast<std::chrono::milliseconds>(clock.now() - t0).count()));
    }
  }
  EXPECT_EQ(port.writes, writesBefore);  // nothing written without a link
  // Loss seen at 10 ms; attempts after 100, 200, 400, 800, 1600, then every 2000 ms.
  const std::vector<long> expected{110, 310, 710, 1510, 3110, 5110, 7110, 9110, 11110};
  EXPECT_EQ(attemptsMs, expected);

  // Meanwhile the PLC has reduced the applied offsets by itself (e.g. its own ramp).
  port.applied = {0.0, -0.005, 0.012};
  port.connectError = {};
  CycleReport r{};
  for (int i = 0; i < 300 && !r.wrote; ++i) r = cycle();
  ASSERT_TRUE(r.wrote);
  EXPECT_EQ(r.state, LoopState::Active);
  EXPECT_TRUE(has(port.last.status, status::kReconnected));
  // Continues from the read-back: within one step of it, never a jump to the old value.
  EXPECT_NEAR(port.last.offsetMm[2], 0.012 + kStep, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], -0.005 - kStep, kEps);
  EXPECT_EQ(loop->counters().reconnects, 1u);
}

TEST_F(LoopTest, FailedWriteBeforeALinkLossDoesNotFaultAfterReconnecting) {
  make();
  cycle();
  port.writeError = std::make_error_code(std::errc::timed_out);
  cycle();
  port.writeError = {};
  port.dropLink();
  EXPECT_EQ(cycle().state, LoopState::LinkLost);
  for (int i = 0; i < 10; ++i) cycle();  // reconnect after 100 ms
  EXPECT_EQ(loop->counters().linkLosses, 1u);
  EXPECT_EQ(loop->counters().reconnects, 1u);
  EXPECT_EQ(loop->state(), LoopState::Active);
  EXPECT_EQ(loop->fault(), FaultCode::None);
}

TEST_F(LoopTest, LinkErrorOnWriteEntersLinkLost) {
  make();
  cycle();
  port.writeError = std::make_error_code(std::errc::broken_pipe);
  EXPECT_EQ(cycle().state, LoopState::LinkLost);
  EXPECT_FALSE(port.connected());
}

TEST_F(LoopTest, FirstConnectFailureIsLinkLostAndRetried) {
  port.connectError = std::make_error_code(std::errc::connection_refused);
  make();
  EXPECT_EQ(cycle().state, LoopState::LinkLost);
  port.connectError = {};
  for (int i = 0; i < 9; ++i) cycle();  // 100 ms backoff
  EXPECT_EQ(port.writes, 0);
  EXPECT_TRUE(cycle().wrote);
  EXPECT_FALSE(has(port.last.status, status::kReconnected));  // a first connect, not a reconnect
}

// --- stopping --------------------------------------------------------------------------------

TEST_F(LoopTest, StoppingRampsToZeroWritesZeroInactiveThenFinishes) {
  make();
  runUntilSettled();
  loop->requestStop();
  std::vector<OffsetCommand> writes;
  for (int i = 0; i < 20 && !loop->finished(); ++i) {
    const int before = port.writes;
    cycle();
    if (port.writes != before) writes.push_back(port.last);
  }
  ASSERT_TRUE(loop->finished());
  ASSERT_EQ(writes.size(), 3u);  // 0.03 -> 0.02 -> 0.01 -> 0
  EXPECT_NEAR(writes[0].offsetMm[2], 0.02, kEps);
  EXPECT_EQ(writes[0].status & status::kStopping, status::kStopping);
  EXPECT_NEAR(writes[1].offsetMm[2], 0.01, kEps);
  for (double o : writes[2].offsetMm) EXPECT_EQ(o, 0.0);
  EXPECT_EQ(writes[2].status, 0);  // inactive
  const int total = port.writeCalls;
  cycle();
  EXPECT_EQ(port.writeCalls, total);  // nothing after finishing
}

TEST_F(LoopTest, StopWhileLinkIsLostFinishesAtOnce) {
  make();
  cycle();
  port.dropLink();
  port.connectError = std::make_error_code(std::errc::connection_refused);
  cycle();
  loop->requestStop();
  EXPECT_EQ(cycle().state, LoopState::Finished);
}

TEST_F(LoopTest, StopGivesUpAfterABoundedTimeWhenWritesKeepFailing) {
  make();
  runUntilSettled();
  port.writeError = std::make_error_code(std::errc::timed_out);
  loop->requestStop();
  // Ramp 0.03 mm at 1 mm/s = 30 ms; deadline 2 x 30 ms + 1 s.
  int cycles = 0;
  while (!loop->finished() && cycles < 1000) {
    cycle();
    ++cycles;
  }
  EXPECT_TRUE(loop->finished());
  EXPECT_LE(cycles, 107);
}

// --- position semantics ----------------------------------------------------------------------

TEST_F(LoopTest, ActualSemanticsSubtractsTheAppliedOffsetSoItDoesNotFeedBack) {
  port.semanticsActual = true;  // controller reports q + applied offset
  settings.semantics = loop::PositionSemantics::Actual;
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.applied[2], 0.03);
  cycle();
  EXPECT_NEAR(model->lastQ[0], 100.0, kEps);
  EXPECT_NEAR(model->lastQ[1], 50.0, kEps);
  EXPECT_NEAR(model->lastQ[2], -20.0, kEps);
}

TEST_F(LoopTest, ActualSemanticsWithoutReadBackSubtractsTheLastWrittenOffset) {
  port.semanticsActual = true;
  settings.semantics = loop::PositionSemantics::Actual;
  settings.offsetReadback = false;
  settings.plcZeroAfter = std::chrono::milliseconds(10);
  make();
  runUntilSettled();
  port.readback = false;
  cycle();
  EXPECT_NEAR(model->lastQ[2], -20.0, kEps);
}

TEST_F(LoopTest, CommandedSemanticsEvaluatesThePositionAsRead) {
  port.semanticsActual = true;  // a misconfiguration: the register includes the offset
  make();
  runUntilSettled();
  cycle();
  // The model then sees q + o: this is the feedback the `actual` setting prevents.
  EXPECT_NEAR(model->lastQ[2], -20.0 + 0.03, kEps);
}

// --- reload ----------------------------------------------------------------------------------

TEST_F(LoopTest, NewModelSlewsInThroughTheLimiter) {
  make();
  runUntilSettled();
  auto next = std::make_shared<FakeModel>(std::array<double, 3>{0.01, -0.02, 0.3});
  loop->setModel(next);
  cycle();
  EXPECT_NEAR(port.last.offsetMm[2], 0.03 + kStep, kEps);  // no jump to 0.3
  EXPECT_TRUE(has(port.last.status, status::kModelReloaded));
  for (int i = 0; i < 100; ++i) cycle();
  EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.3);
  EXPECT_FALSE(has(port.last.status, status::kModelReloaded));  // held for 1 s only
  EXPECT_GT(next->calls, 0);
}

TEST_F(LoopTest, RejectedReloadKeepsTheOldModelAndSetsTheBit) {
  make();
  runUntilSettled();
  const int callsBefore = model->calls;
  loop->noteReloadFailed();
  cycle();
  EXPECT_TRUE(has(port.last.status, status::kReloadFailed));
  EXPECT_TRUE(has(port.last.status, status::kActive));
  EXPECT_EQ(model->calls, callsBefore + 1);
  EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  loop->setModel(model);  // a later good reload clears it
  cycle();
  EXPECT_FALSE(has(port.last.status, status::kReloadFailed));
}

TEST_F(LoopTest, NewSettingsTakeEffectButNotThePeriod) {
  make();
  runUntilSettled();
  LoopSettings changed = settings;
  changed.limiter = LimiterSettings::uniform(0.015, 1.0);
  changed.period = std::chrono::milliseconds(1);
  loop->setSettings(changed);
  EXPECT_EQ(loop->settings().period, std::chrono::milliseconds(10));
  cycle();
  EXPECT_NEAR(port.last.offsetMm[2], 0.02, kEps);  // slews into the smaller band
  cycle();
  EXPECT_NEAR(port.last.offsetMm[2], 0.015, kEps);
}

}  // namespace
}  // namespace volcomp::loop::testing
