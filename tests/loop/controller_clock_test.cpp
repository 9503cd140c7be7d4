// Mapping a controller's 16-bit sample timestamp onto the daemon's clock.
#include "volcomp/loop/controller_clock.hpp"
#include "volcomp/loop/window_minimum.hpp"

#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

namespace volcomp::loop {
namespace {

using namespace std::chrono_literals;
using time_point = ControllerClock::time_point;

constexpr double kTickS = 1e-6;  // 1 us ticks: the counter wraps every 65.5 ms

std::uint16_t stamp(double controllerS) {
  return static_cast<std::uint16_t>(static_cast<std::int64_t>(std::llround(controllerS / kTickS)) &
                                    0xFFFF);
}

double secondsBetween(time_point a, time_point b) {
  return std::chrono::duration<double>(a - b).count();
}

// A PLC scan of 4 ms latches the positions; the daemon reads every 10 ms and the reply takes
// 0.2-0.5 ms. The controller's clock starts at an arbitrary 1.234 s before the daemon's epoch and
// runs through many wraps.
TEST(ControllerClock, MapsEachLatchToWithinTheLeastTransportDelayAcrossWraps) {
  ControllerClock clock;
  const time_point epoch{std::chrono::seconds(1000)};
  double worstS = 0.0;
  for (int i = 1; i <= 1000; ++i) {
    const double readS = 0.010 * i;
    const double latchS = std::floor(readS / 0.004) * 0.004;
    const double delayS = 0.0002 + 0.0003 * ((i * 7) % 11) / 10.0;
    const time_point reply = epoch + std::chrono::nanoseconds(std::llround((readS + delayS) * 1e9));
    const time_point latched = clock.latchedAt(stamp(latchS + 1.234), kTickS, reply, 20ms);
    EXPECT_LE(latched, reply);
    const double errorS = secondsBetween(latched, epoch) - latchS;
    // Never earlier than the true latch; later by at most the least delay seen so far.
    EXPECT_GE(errorS, -1e-9) << i;
    if (i >= 22)
      worstS = std::max(worstS, errorS);  // from the first 0.2 ms reply of a fresh latch on
  }
  EXPECT_LE(worstS, 0.0002 + 1e-9);
  EXPECT_EQ(clock.samples(), kClockWindow);
}

TEST(ControllerClock, TheSameStampReadAgainIsNoNewLatch) {
  ControllerClock clock;
  const time_point t0{std::chrono::seconds(5)};
  const time_point a = clock.latchedAt(stamp(0.5), kTickS, t0, 20ms);
  EXPECT_EQ(clock.stamps(), 1U);
  const time_point b = clock.latchedAt(stamp(0.5), kTickS, t0 + 3ms, 20ms);
  EXPECT_EQ(clock.stamps(), 1U);
  EXPECT_EQ(a, b);
  clock.latchedAt(stamp(0.504), kTickS, t0 + 4ms, 20ms);
  EXPECT_EQ(clock.stamps(), 2U);
}

// A late cycle, longer than a wrap: the daemon's own elapsed time tells how many wraps passed.
TEST(ControllerClock, AGapOfSeveralWrapsIsUnwrappedByTheElapsedTime) {
  ControllerClock clock;
  const time_point t0{std::chrono::seconds(7)};
  clock.latchedAt(stamp(2.0), kTickS, t0, 20ms);
  const time_point later = clock.latchedAt(stamp(2.2), kTickS, t0 + 200ms, 20ms);
  EXPECT_NEAR(secondsBetween(later, t0), 0.2, 1e-9);
  EXPECT_EQ(clock.samples(), 2U);
}

// Crystals 100 ppm apart over 20 s: the window follows the drift.
TEST(ControllerClock, FollowsADriftingControllerClock) {
  ControllerClock clock;
  const time_point epoch{std::chrono::seconds(1)};
  double worstS = 0.0;
  for (int i = 1; i <= 2000; ++i) {
    const double latchS = 0.010 * i;  // the daemon's time of the latch
    const time_point reply = epoch + std::chrono::nanoseconds(std::llround((latchS + 3e-4) * 1e9));
    const time_point latched = clock.latchedAt(stamp(latchS * (1.0 + 1e-4)), kTickS, reply, 20ms);
    worstS = std::max(worstS, std::abs(secondsBetween(latched, epoch) - latchS));
  }
  EXPECT_LT(worstS, 3e-4 + 0.2e-3);
}

// A stamp that has hardly moved while the daemon's clock ran on 30 ms (a controller that restarted
// its clock near the old value) would map the latch 30 ms back: past the 20 ms bound, the mapping
// starts anew from this sample.
TEST(ControllerClock, ALatchMappedFurtherBackThanMaxAgeStartsTheMappingAnew) {
  ControllerClock clock;
  const time_point t0{std::chrono::seconds(9)};
  for (int i = 0; i < 10; ++i) clock.latchedAt(stamp(30.0 + 0.01 * i), kTickS, t0 + i * 10ms, 20ms);
  const time_point reply = t0 + 120ms;
  const auto barelyMoved = static_cast<std::uint16_t>(stamp(30.09) + 5);
  EXPECT_EQ(clock.latchedAt(barelyMoved, kTickS, reply, 20ms), reply);
  EXPECT_EQ(clock.samples(), 1U);
  // Within the bound the mapping holds: 10 ms on, 10 ms of stamp.
  const time_point next =
      clock.latchedAt(static_cast<std::uint16_t>(barelyMoved + 10000), kTickS, reply + 10ms, 20ms);
  EXPECT_EQ(next, reply + 10ms);
  EXPECT_EQ(clock.samples(), 2U);
}

TEST(ControllerClock, NoTickSizeIsNoTimestamp) {
  ControllerClock clock;
  const time_point t0{std::chrono::seconds(3)};
  EXPECT_EQ(clock.latchedAt(123, 0.0, t0, 20ms), t0);
  EXPECT_EQ(clock.samples(), 0U);
}

}  // namespace
}  // namespace volcomp::loop

namespace volcomp::loop::testing {
namespace {

// The window keeps the smallest of the last N values: a small one counts until N more have come,
// a reset forgets everything.
TEST(WindowMinimum, KeepsTheSmallestOfTheLastN) {
  using std::chrono::nanoseconds;
  WindowMinimum<4> w;
  EXPECT_EQ(w.min(), nanoseconds(0));
  w.push(nanoseconds(5));
  w.push(nanoseconds(2));
  w.push(nanoseconds(7));
  EXPECT_EQ(w.min(), nanoseconds(2));
  for (int i = 0; i < 3; ++i) w.push(nanoseconds(9));
  EXPECT_EQ(w.min(), nanoseconds(7));  // 5 and 2 have left: 9, 9, 7, 9 held
  w.push(nanoseconds(9));
  EXPECT_EQ(w.min(), nanoseconds(9));
  EXPECT_EQ(w.size(), 4U);
  w.reset();
  EXPECT_EQ(w.size(), 0U);
  w.push(nanoseconds(11));
  EXPECT_EQ(w.min(), nanoseconds(11));
}

}  // namespace
}  // namespace volcomp::loop::testing
