#include "volcomp/linuxcnc/offset_counts.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>

namespace volcomp::linuxcnc {
namespace {

constexpr double kCountsPerMm = 10000.0;
constexpr double kCountMm = 1.0 / kCountsPerMm;

// LinuxCNC's motion controller as it treats one axis' external offset (axis.c,
// axis_plan_external_offsets, 2.9): every servo period the change of the counts since the last
// period is added to the request, unless it is not accepting (then the change is dropped, the
// previous counts are updated regardless); a clear zeroes the request; machine-on zeroes it.
struct FakeMotion {
  std::int32_t oldCounts = 0;
  double requestMm = 0.0;
  void servo(std::int32_t counts, bool accepting, bool clear = false) {
    // int delta = new - old, which wraps like 32-bit two's complement.
    const auto delta = static_cast<std::int32_t>(static_cast<std::uint32_t>(counts) -
                                                 static_cast<std::uint32_t>(oldCounts));
    oldCounts = counts;
    if (clear) {
      requestMm = 0.0;
      return;
    }
    if (accepting) requestMm += delta * kCountMm;
  }
};

TEST(OffsetCounts, AbsoluteOffsetsBecomeTheRequestWhileAccepting) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  c.adopt(0);
  for (double o : {0.0, 0.0012, 0.0025, -0.0031, 0.0}) {
    m.servo(c.next(o, true, m.requestMm), true);
    EXPECT_NEAR(m.requestMm, o, 1e-12) << o;
  }
  EXPECT_EQ(c.rebases(), 1u);  // the first accepting cycle takes the base from the request
}

TEST(OffsetCounts, JoinsCountsAndARequestLeftByAPredecessor) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  m.oldCounts = 123456;  // what the HAL signal holds after a previous daemon
  m.requestMm = 0.0042;  // and what LinuxCNC applies because of it
  c.adopt(123456);
  m.servo(c.next(0.0041, true, m.requestMm), true);
  EXPECT_NEAR(m.requestMm, 0.0041, 1e-12);  // one step from what is applied, not a jump
}

TEST(OffsetCounts, ANewWriteTheServoHasNotSeenYetIsNoInconsistency) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  c.adopt(0);
  m.servo(c.next(0.001, true, m.requestMm), true);
  // Two writes before the servo thread runs (the daemon's cycle is faster than it, or it stalled).
  std::int32_t counts = c.next(0.002, true, m.requestMm);
  counts = c.next(0.003, true, m.requestMm);
  counts = c.next(0.004, true, m.requestMm);
  m.servo(counts, true);
  EXPECT_NEAR(m.requestMm, 0.004, 1e-12);
  m.servo(c.next(0.005, true, m.requestMm), true);
  EXPECT_NEAR(m.requestMm, 0.005, 1e-12);
  EXPECT_EQ(c.rebases(), 1u);
}

TEST(OffsetCounts, ChangesAreHeldWhileNotAcceptingAndTheBaseIsRetakenAfter) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  c.adopt(0);
  m.servo(c.next(0.003, true, m.requestMm), true);
  ASSERT_NEAR(m.requestMm, 0.003, 1e-12);
  // Not homed: LinuxCNC keeps 0.003 and would drop any change; the counts do not move.
  const std::int32_t held = c.counts();
  for (double o : {0.002, 0.001, 0.0}) {
    EXPECT_EQ(c.next(o, false, m.requestMm), held);
    m.servo(c.counts(), false);
  }
  EXPECT_TRUE(c.rebasePending());
  // Homed again: the offset written now is what LinuxCNC requests.
  m.servo(c.next(0.0029, true, m.requestMm), true);
  EXPECT_NEAR(m.requestMm, 0.0029, 1e-12);
}

TEST(OffsetCounts, MachineOnZeroesTheRequestAndTheNextOffsetIsStillAbsolute) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  c.adopt(0);
  m.servo(c.next(0.004, true, m.requestMm), true);
  c.next(0.003, false, m.requestMm);  // machine off
  m.servo(c.counts(), false);
  m.requestMm = 0.0;  // machine on: LinuxCNC zeroes its offsets
  m.servo(c.next(0.0001, true, m.requestMm), true);
  EXPECT_NEAR(m.requestMm, 0.0001, 1e-12);
}

TEST(OffsetCounts, AClearBehindItsBackHoldsOneCycleThenContinuesFromZero) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  c.adopt(0);
  m.servo(c.next(0.004, true, m.requestMm), true);
  // The daemon was silent (stopped, starved) and the heartbeat watchdog cleared the offsets.
  m.servo(c.counts(), true, /*clear=*/true);
  const std::int32_t held = c.counts();
  // Departed from the last counts: held while it settles. (The request, 0, equals counts written
  // before the last ones, but after a silence only the last ones count.)
  EXPECT_EQ(c.next(0.004, true, m.requestMm, /*afterSilence=*/true), held);
  m.servo(c.counts(), true);
  EXPECT_NEAR(m.requestMm, 0.0, 1e-12);
  m.servo(c.next(0.0005, true, m.requestMm), true);
  EXPECT_NEAR(m.requestMm, 0.0005, 1e-12);
}

TEST(OffsetCounts, CountsWrapAtTheEndsOfTheThirtyTwoBitPinAsLinuxCncDifferencesThem) {
  OffsetCounts c(kCountsPerMm);
  FakeMotion m;
  m.oldCounts = std::numeric_limits<std::int32_t>::max() - 10;
  c.adopt(m.oldCounts);
  m.servo(c.next(0.0, true, m.requestMm), true);
  m.servo(c.next(0.005, true, m.requestMm), true);  // +50 counts across the wrap
  EXPECT_LT(c.counts(), 0);
  EXPECT_NEAR(m.requestMm, 0.005, 1e-12);
  m.servo(c.next(-0.005, true, m.requestMm), true);  // and back
  EXPECT_NEAR(m.requestMm, -0.005, 1e-12);
}

TEST(OffsetCounts, NonFiniteInputsHoldTheCounts) {
  OffsetCounts c(kCountsPerMm);
  c.adopt(7);
  const std::int32_t held = c.next(std::numeric_limits<double>::quiet_NaN(), true, 0.0);
  EXPECT_EQ(held, 7);
  EXPECT_EQ(c.next(0.001, true, std::numeric_limits<double>::infinity()), 7);
}

// Random schedules of acceptance, servo lag, machine-on resets and clears: once LinuxCNC accepts
// and has seen the writes, its request is the offset last written, to a count.
TEST(OffsetCounts, RandomSchedulesEndWithTheRequestOnTheLastOffset) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  std::uniform_int_distribution<int> die(0, 99);
  for (int run = 0; run < 200; ++run) {
    OffsetCounts c(kCountsPerMm);
    FakeMotion m;
    m.oldCounts = static_cast<std::int32_t>(rng());
    c.adopt(m.oldCounts);
    bool accepting = true;
    double last = 0.0;
    bool silent = false;  // LinuxCNC acted on its own since the last write
    for (int step = 0; step < 300; ++step) {
      last = std::round(offset(rng) * kCountsPerMm) / kCountsPerMm;
      const std::int32_t counts = c.next(last, accepting, m.requestMm, silent);
      silent = false;
      const int roll = die(rng);
      // Behind the adapter's back, during a silence of the daemon: acceptance flips, a
      // machine-on, a clear.
      if (roll < 3) {
        accepting = !accepting;
        silent = true;
      }
      if (roll == 3 && !accepting) {
        m.requestMm = 0.0;
        silent = true;
      }
      const bool clear = roll == 4 && accepting;
      silent = silent || clear;
      // The servo thread runs between zero and three times per write.
      const int servos = die(rng) % 4;
      for (int s = 0; s < servos; ++s) m.servo(counts, accepting, clear && s == 0);
    }
    // Settle: LinuxCNC accepts, the daemon keeps writing the same offset.
    for (int i = 0; i < 4; ++i) {
      m.servo(c.next(last, true, m.requestMm, silent), true);
      silent = false;
    }
    ASSERT_NEAR(m.requestMm, last, 0.5 * kCountMm) << "run " << run;
  }
}

}  // namespace
}  // namespace volcomp::linuxcnc
