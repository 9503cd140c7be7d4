// The loop under timing faults, with the fake clock: writes whose outcome is unknown,
// a pause between the read and the write of a cycle, steps per measured time rather than per
// cycle, a read-back outside the band, and the bounded stop. Every write is checked against
// what the fake controller applies at that moment.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <system_error>
#include <vector>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

using namespace std::chrono_literals;

constexpr double kStep = 0.01;  // max rate 1 mm/s * 10 ms
constexpr double kEps = 1e-12;

class TimingFaults : public LoopTest {
 protected:
  /// A cycle `late` after its deadline (the clock advances by the period plus `late`; the next
  /// cycle() comes back to the grid by advancing less).
  CycleReport cycleAfter(std::chrono::nanoseconds sincePrevious) {
    clock.advance(sincePrevious);
    return loop->step();
  }
  /// Largest per-axis distance between two offset vectors.
  static double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    double d = 0.0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(a[k] - b[k]));
    return d;
  }
};

// --- unknown outcome -----------------------------------------------------------------------

// The reply of a write is lost but the controller applied it. In the fault that follows the
// offsets ramp out, each write within one step of what the controller really applies; the old
// rule (roll back to the acknowledged value) wrote two steps below the applied value.
TEST_F(TimingFaults, AppliedWriteWithALostReplyGetsNoJump) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  for (int i = 0; i < 10; ++i) cycle();
  ASSERT_NEAR(port.applied[2], 0.1, kEps);
  port.applyFailedWrites = true;
  port.writeError = std::make_error_code(std::errc::timed_out);
  std::vector<double> applied{port.applied[2]};
  for (int i = 0; i < 3; ++i) {  // three applied writes in a row counted as failed
    EXPECT_TRUE(cycle().unknownOutcome);
    applied.push_back(port.applied[2]);
  }
  port.writeError = {};
  for (int i = 0; i < 20; ++i) {
    const double before = port.applied[2];
    cycle();
    EXPECT_LE(std::abs(port.applied[2] - before), kStep + kEps) << "cycle " << i;
  }
  for (std::size_t i = 1; i < applied.size(); ++i) {
    EXPECT_LE(std::abs(applied[i] - applied[i - 1]), kStep + kEps);
  }
  EXPECT_EQ(loop->counters().unknownOutcomes, 3u);
}

// The same when the controller did NOT apply the failed writes: the values written stay within
// one step of the acknowledged one too.
TEST_F(TimingFaults, NotAppliedFailedWritesGetNoJumpEither) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  for (int i = 0; i < 10; ++i) cycle();
  const double acknowledged = port.applied[2];
  port.writeError = std::make_error_code(std::errc::timed_out);
  for (int i = 0; i < 3; ++i) cycle();
  ASSERT_DOUBLE_EQ(port.applied[2], acknowledged);
  port.writeError = {};
  const double before = port.applied[2];
  cycle();
  EXPECT_LE(std::abs(port.applied[2] - before), kStep + kEps);
}

// After an unknown outcome the window [attempted - step, acknowledged + step] is empty when the
// next write comes much earlier than a period (dt < half the step that made the envelope): the
// loop then writes nothing and tries again at the next cycle.
TEST_F(TimingFaults, UnknownOutcomeWithATooShortDtWritesNothingThatCycle) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  for (int i = 0; i < 5; ++i) cycle();
  port.writeError = std::make_error_code(std::errc::timed_out);
  cycle();  // attempted 0.06 from the acknowledged 0.05
  port.writeError = {};
  const int writes = port.writes;
  const CycleReport early = cycleAfter(2ms);  // step 0.002: nothing within it of both
  EXPECT_EQ(early.withheld, Withheld::UnknownOutcome);
  EXPECT_EQ(port.writes, writes);
  const CycleReport next = cycleAfter(8ms);
  EXPECT_TRUE(next.wrote);
  EXPECT_LE(std::abs(port.last.offsetMm[2] - 0.05), kStep + kEps);
  EXPECT_LE(std::abs(port.last.offsetMm[2] - 0.06), kStep + kEps);
}

// --- steps per measured time ---------------------------------------------------------------

// A cycle 8 ms late followed by one on its deadline (2 ms later): the second step is limited to
// max_rate x 2 ms, so the offset never moves faster than max_rate over any window.
TEST_F(TimingFaults, LateCycleThenOnTimeCycleDoesNotBunchSteps) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  cycle();
  ASSERT_NEAR(port.last.offsetMm[2], kStep, kEps);
  cycleAfter(18ms);  // late: a full step (dt capped at one period)
  EXPECT_NEAR(port.last.offsetMm[2], 2 * kStep, kEps);
  cycleAfter(2ms);  // on time again
  EXPECT_NEAR(port.last.offsetMm[2], 2 * kStep + 0.002, kEps);
  cycleAfter(10ms);
  EXPECT_NEAR(port.last.offsetMm[2], 3 * kStep + 0.002, kEps);
}

// A write held up on its way to the controller (7.8 ms where every transaction takes 0.2 ms) may
// be applied just before the next one, sent on time: the next step is limited to max_rate x the
// time since its reply plus the undelayed round trip (2.4 ms), not since it was sent (10 ms). The
// step after that is a full one again.
TEST_F(TimingFaults, AWriteHeldUpOnItsWayShortensTheNextStep) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  std::chrono::nanoseconds writeTime = 200us;
  port.afterRead = [&] { clock.advance(200us); };
  port.duringWrite = [&] { clock.advance(writeTime); };
  cycle();
  for (int i = 0; i < 3; ++i) cycleAfter(10ms - 400us);  // writes sent 10 ms apart
  ASSERT_NEAR(port.last.offsetMm[2], 4 * kStep, kEps);
  writeTime = 7800us;
  cycleAfter(10ms - 400us);
  ASSERT_NEAR(port.last.offsetMm[2], 5 * kStep, kEps);
  writeTime = 200us;
  cycleAfter(10ms - 200us - 7800us);  // sent 10 ms after the held one, 2.2 ms after its reply
  EXPECT_NEAR(port.last.offsetMm[2], 5 * kStep + 0.0024, kEps);
  cycleAfter(10ms - 400us);
  EXPECT_NEAR(port.last.offsetMm[2], 6 * kStep + 0.0024, kEps);
}

// A controller that is slow on every transaction (4 ms) loses nothing: a steady round trip is not
// a delay.
TEST_F(TimingFaults, AUniformlySlowControllerKeepsTheFullStep) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  port.afterRead = [&] { clock.advance(4ms); };
  port.duringWrite = [&] { clock.advance(4ms); };
  cycle();
  for (int i = 0; i < 5; ++i) cycleAfter(2ms);  // writes sent 10 ms apart
  EXPECT_NEAR(port.last.offsetMm[2], 6 * kStep, kEps);
}

// The smallest round trip is that of the last 128 transactions: after the route to the controller
// became slower (every transaction 4 ms instead of none) the steps are short until the fast ones
// have left the window (64 cycles of a read and a write), then full again.
TEST_F(TimingFaults, TheSmallestRoundTripIsForgottenAfter128Transactions) {
  model->setOffset({0.0, 0.0, 0.5});
  make();
  for (int i = 0; i < 3; ++i) cycle();
  ASSERT_NEAR(port.last.offsetMm[2], 3 * kStep, kEps);
  port.afterRead = [&] { clock.advance(4ms); };
  port.duringWrite = [&] { clock.advance(4ms); };
  std::vector<double> steps;
  for (int i = 0; i < 67; ++i) {
    const double before = port.last.offsetMm[2];
    cycleAfter(2ms);  // writes sent 10 ms apart
    steps.push_back(port.last.offsetMm[2] - before);
  }
  EXPECT_NEAR(steps.front(), 0.006, kEps);  // 6 ms since the last reply, 0 ms fastest
  EXPECT_NEAR(steps[60], 0.006, kEps);
  EXPECT_NEAR(steps.back(), kStep, kEps);
}

// A write that timed out (given up on after 25 ms) may still reach the controller at any moment:
// the next cycle, run at once, is within the envelope of both values for the time since giving
// up, so it writes nothing until that time allows a common value.
TEST_F(TimingFaults, AWriteGivenUpOnCountsFromWhenItWasGivenUp) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  for (int i = 0; i < 5; ++i) cycle();
  port.writeError = std::make_error_code(std::errc::timed_out);
  port.applyFailedWrites = true;
  port.duringWrite = [&] { clock.advance(25ms); };
  EXPECT_TRUE(cycle().unknownOutcome);  // attempted 0.06 from the acknowledged 0.05
  port.writeError = {};
  port.duringWrite = nullptr;
  const int writes = port.writes;
  EXPECT_EQ(cycleAfter(0ms).withheld, Withheld::UnknownOutcome);  // 25 ms since it was sent
  EXPECT_EQ(port.writes, writes);
  EXPECT_TRUE(cycleAfter(5ms).wrote);
  EXPECT_LE(std::abs(port.last.offsetMm[2] - 0.05), 0.005 + kEps);
  EXPECT_LE(std::abs(port.last.offsetMm[2] - 0.06), 0.005 + kEps);
}

// A gap (a silence of a second) allows one step, not a second's worth.
TEST_F(TimingFaults, GapAllowsOneStepOnly) {
  model->setOffset({0.0, 0.0, 0.3});
  make();
  cycle();
  cycleAfter(1s);
  EXPECT_NEAR(port.last.offsetMm[2], 2 * kStep, kEps);
}

// The acceleration limit works on the measured dt too: the velocity changes by at most
// max_accel x dt between two writes, whatever their spacing.
TEST_F(TimingFaults, AccelerationLimitUsesTheMeasuredDt) {
  settings.limiter = LimiterSettings::uniform(0.5, 1.0, 20.0);
  model->setOffset({0.0, 0.0, 0.3});
  make();
  double previousOffset = 0.0, previousVelocity = 0.0;
  const std::chrono::milliseconds spacing[] = {10ms, 10ms, 3ms, 17ms, 1ms, 9ms, 10ms, 30ms, 2ms};
  for (int round = 0; round < 5; ++round) {
    for (const auto dt : spacing) {
      cycleAfter(dt);
      const double dtS =
          std::chrono::duration<double>(std::min<std::chrono::nanoseconds>(dt, settings.period))
              .count();
      const double v = (port.last.offsetMm[2] - previousOffset) / dtS;
      EXPECT_LE(std::abs(v - previousVelocity), 20.0 * dtS + 1e-9);
      EXPECT_LE(std::abs(v), 1.0 + 1e-9);
      previousOffset = port.last.offsetMm[2];
      previousVelocity = v;
    }
  }
}

// Per-axis limits: each axis slews at its own rate and clamps at its own band.
TEST_F(TimingFaults, EachAxisHasItsOwnLimits) {
  settings.limiter.axes[0] = {0.05, 1.0, 0.0};
  settings.limiter.axes[1] = {0.5, 0.5, 0.0};
  settings.limiter.axes[2] = {0.5, 2.0, 0.0};
  model->setOffset({0.1, 0.1, 0.1});
  make();
  cycle();
  EXPECT_NEAR(port.last.offsetMm[0], 0.01, kEps);
  EXPECT_NEAR(port.last.offsetMm[1], 0.005, kEps);
  EXPECT_NEAR(port.last.offsetMm[2], 0.02, kEps);
  for (int i = 0; i < 100; ++i) cycle();
  EXPECT_DOUBLE_EQ(port.last.offsetMm[0], 0.05);  // clamped
  EXPECT_DOUBLE_EQ(port.last.offsetMm[1], 0.1);
  EXPECT_DOUBLE_EQ(port.last.offsetMm[2], 0.1);
}

// --- read-to-write time ----------------------------------------------------------------------

// The process is stopped between the read and the write (here: the clock jumps 400 ms inside
// read()) while the controller's watchdog removes the offsets. The loop reads again and writes
// one step from what is applied now, never from the old read-back.
TEST_F(TimingFaults, PauseBetweenReadAndWriteReadsAgain) {
  settings.readToWriteMax = 25ms;
  make();
  runUntilSettled();
  ASSERT_DOUBLE_EQ(port.last.offsetMm[2], 0.03);
  bool paused = false;
  port.afterRead = [&] {
    if (paused) return;
    paused = true;
    clock.advance(400ms);
    port.applied = {0.0, 0.0, 0.0};  // the PLC's heartbeat watchdog ramped them out
  };
  const CycleReport r = cycle();
  ASSERT_TRUE(r.wrote);
  EXPECT_EQ(loop->counters().lateReads, 1u);
  EXPECT_LE(distance(port.last.offsetMm, {0.0, 0.0, 0.0}), kStep + kEps);
  EXPECT_EQ(loop->counters().resynchronisations, 1u);
}

// Both reads of a cycle late (a controller answering slowly, or stopped again): nothing is
// written in that cycle.
TEST_F(TimingFaults, TwoLateReadsWriteNothing) {
  settings.readToWriteMax = 25ms;
  make();
  runUntilSettled();
  const int writes = port.writes;
  port.afterRead = [&] { clock.advance(30ms); };
  const CycleReport r = cycle();
  EXPECT_EQ(r.withheld, Withheld::StaleRead);
  EXPECT_EQ(port.writes, writes);
  port.afterRead = nullptr;
  EXPECT_TRUE(cycle().wrote);
}

// A read that is slow but within the bound is used as it is.
TEST_F(TimingFaults, ReadWithinTheBoundIsUsed) {
  settings.readToWriteMax = 25ms;
  make();
  runUntilSettled();
  port.afterRead = [&] { clock.advance(20ms); };
  EXPECT_TRUE(cycle().wrote);
  EXPECT_EQ(loop->counters().lateReads, 0u);
}

// A read-back adopted after a silence must be written within one period: the controller may be
// ramping at that moment.
TEST_F(TimingFaults, AdoptedReadBackAllowsOnePeriodOnly) {
  settings.readToWriteMax = 25ms;
  make();
  runUntilSettled();
  clock.advance(400ms);  // silence
  bool once = false;
  port.afterRead = [&] {
    if (!once) clock.advance(15ms);  // > one period, < readToWriteMax
    once = true;
  };
  EXPECT_TRUE(cycle().wrote);
  EXPECT_EQ(loop->counters().lateReads, 1u);
}

// --- read-back outside the band ----------------------------------------------------------

// At start the controller reports 150 mm applied (a garbled reply) or more than the band: the
// fault readback-out-of-range, and nothing is written until it reports offsets inside the band.
TEST_F(TimingFaults, ReadBackOutsideTheBandAtStartIsAFaultAndNothingIsWritten) {
  port.holdApplied = true;
  port.applied = {150.0, 0.0, 0.0};
  make();
  for (int i = 0; i < 20; ++i) {
    const CycleReport r = cycle();
    EXPECT_EQ(r.fault, FaultCode::ReadbackOutOfRange);
    EXPECT_EQ(r.state, LoopState::Starting);
  }
  EXPECT_EQ(port.writeCalls, 0);
  port.applied = {0.5 + 0.001, 0.0, 0.0};  // just outside 0.5
  cycle();
  EXPECT_EQ(port.writeCalls, 0);
  port.applied = {0.2, 0.0, 0.0};  // inside: taken over, one step from it
  port.holdApplied = false;
  const CycleReport r = cycle();
  ASSERT_TRUE(r.wrote);
  EXPECT_NEAR(port.last.offsetMm[0], 0.2 - kStep, kEps);
}

// While writing every cycle, a read-back outside the band that is not this loop's own value:
// fault, nothing written (the heartbeat stalls, the controller's watchdog takes over); when the
// read-back is inside again the loop continues from it, never past max_offset.
TEST_F(TimingFaults, GarbledReadBackWhileActiveWithholdsTheWrite) {
  settings.faultLatch = false;
  make();
  runUntilSettled();
  port.holdApplied = true;
  const auto good = port.applied;
  port.applied = {150.0, 0.0, 0.0};
  const int writes = port.writes;
  const CycleReport r = cycle();
  EXPECT_EQ(r.fault, FaultCode::ReadbackOutOfRange);
  EXPECT_EQ(r.withheld, Withheld::ReadbackOutOfRange);
  EXPECT_EQ(port.writes, writes);
  port.applied = good;
  port.holdApplied = false;
  EXPECT_TRUE(cycle().wrote);
  for (double o : port.last.offsetMm) EXPECT_LE(std::abs(o), 0.5);
}

// The same with the fault latch (the default): once the read-back is inside again the loop
// writes again, in fault and ramping out from the read-back, until the controller acknowledges
// (here: enable off); it is not held silent by the latched fault.
TEST_F(TimingFaults, LatchedReadBackFaultWritesAgainOnceTheReadBackIsInside) {
  make();
  runUntilSettled();
  port.holdApplied = true;
  const auto good = port.applied;
  port.applied = {150.0, 0.0, 0.0};
  EXPECT_EQ(cycle().withheld, Withheld::ReadbackOutOfRange);
  port.applied = good;
  port.holdApplied = false;
  CycleReport r = cycle();
  EXPECT_TRUE(r.wrote);
  EXPECT_EQ(r.state, LoopState::Fault);
  EXPECT_EQ(r.fault, FaultCode::ReadbackOutOfRange);
  EXPECT_NE(port.last.status & status::kLatched, 0);
  EXPECT_LT(std::abs(port.last.offsetMm[2]), std::abs(good[2]));
  port.sample.enable = false;  // acknowledge
  r = cycle();
  EXPECT_TRUE(r.acknowledged);
  port.sample.enable = true;
  r = cycle();
  EXPECT_EQ(r.state, LoopState::Active);
  EXPECT_EQ(port.last.status & status::kLatched, 0);
}

// The report says once where a read-back outside the band starts (with the values read) and
// once where it ends, however often the latched fault is interrupted in between (a failed read
// is a fault of its own for a cycle), so that the caller logs the values that caused the fault
// rather than those of a later cycle.
TEST_F(TimingFaults, AReadBackOutsideTheBandIsReportedOnceWithItsValuesAndItsEndOnce) {
  make();
  runUntilSettled();
  port.holdApplied = true;
  const auto good = port.applied;
  port.applied = {0.7, -0.02, 0.03};
  int left = 0, back = 0;
  CycleReport first = cycle();
  left += first.readbackLeftBand;
  EXPECT_TRUE(first.readbackLeftBand);
  EXPECT_EQ(first.readbackOutsideMm, port.applied);
  for (int i = 0; i < 10; ++i) {
    port.readError = i % 3 == 0 ? std::make_error_code(std::errc::timed_out) : std::error_code();
    port.applied[0] = 0.7 - 0.01 * i;  // the controller's watchdog ramps it out
    const CycleReport r = cycle();
    left += r.readbackLeftBand;
    back += r.readbackBackInBand;
  }
  EXPECT_EQ(left, 1);
  EXPECT_EQ(back, 0);
  port.readError = {};
  port.applied = good;
  port.holdApplied = false;
  for (int i = 0; i < 10; ++i) {
    port.readError = i % 3 == 0 ? std::make_error_code(std::errc::timed_out) : std::error_code();
    const CycleReport r = cycle();
    left += r.readbackLeftBand;
    back += r.readbackBackInBand;
    EXPECT_EQ(r.state, LoopState::Fault);  // latched until acknowledged
  }
  EXPECT_EQ(left, 1);
  EXPECT_EQ(back, 1);
}

// At start the same: a read-back outside the band reported once, its return into it once (the
// loop then takes it over).
TEST_F(TimingFaults, AReadBackOutsideTheBandAtStartIsReportedOnceAndItsEndOnce) {
  port.holdApplied = true;
  port.applied = {150.0, 0.0, 0.0};
  make();
  int left = 0, back = 0;
  for (int i = 0; i < 20; ++i) {
    const CycleReport r = cycle();
    left += r.readbackLeftBand;
    back += r.readbackBackInBand;
    if (r.readbackLeftBand) {
      EXPECT_EQ(r.readbackOutsideMm[0], 150.0);
    }
  }
  port.applied = {0.2, 0.0, 0.0};
  port.holdApplied = false;
  for (int i = 0; i < 5; ++i) {
    const CycleReport r = cycle();
    left += r.readbackLeftBand;
    back += r.readbackBackInBand;
  }
  EXPECT_EQ(left, 1);
  EXPECT_EQ(back, 1);
}

// A reload that narrows the band below the applied offsets is not a read-back fault: they are
// this loop's own, and return into the band at the rate limit.
TEST_F(TimingFaults, OwnOffsetsOutsideANarrowedBandReturnAtTheRateLimit) {
  make();
  runUntilSettled();
  LoopSettings narrow = settings;
  narrow.limiter = LimiterSettings::uniform(0.015, 1.0);
  loop->setSettings(narrow);
  EXPECT_EQ(cycle().fault, FaultCode::None);
  EXPECT_NEAR(port.last.offsetMm[2], 0.02, kEps);
}

// A stop while the read-back stays outside: nothing can be written; the stop gives up at its
// bounded deadline.
TEST_F(TimingFaults, StopWithTheReadBackOutsideEndsAtTheDeadline) {
  make();
  runUntilSettled();
  port.holdApplied = true;
  port.applied = {150.0, 0.0, 0.0};
  loop->requestStop();
  int cycles = 0;
  while (!loop->finished() && cycles < 10000) {
    cycle();
    ++cycles;
  }
  EXPECT_TRUE(loop->finished());
  EXPECT_LE(cycles, 107);  // 2 x 30 ms ramp + 1 s
}

// The stop deadline never exceeds the stop timeout (the service's TimeoutStopSec), however long
// the ramp would take.
TEST_F(TimingFaults, StopDeadlineIsBoundedByTheStopTimeout) {
  settings.limiter = LimiterSettings::uniform(2.0, 0.01);  // a 200 s ramp for 2 mm
  settings.stopTimeout = 3s;
  model->setOffset({0.0, 0.0, 2.0});
  make();
  for (int i = 0; i < 1000; ++i) cycle();
  loop->requestStop();
  int cycles = 0;
  while (!loop->finished() && cycles < 100000) {
    cycle();
    ++cycles;
  }
  EXPECT_TRUE(loop->finished());
  EXPECT_LE(cycles, 301);
  EXPECT_GT(std::abs(port.last.offsetMm[2]), 0.0) << "not ramped out: the PLC's watchdog does it";
}

}  // namespace
}  // namespace volcomp::loop::testing
