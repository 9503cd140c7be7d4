// The saturation monitor on its own: how long the clamp has held an axis, when the warning
// starts and when sustained limiting becomes a fault.
#include "volcomp/loop/saturation_monitor.hpp"

#include <gtest/gtest.h>

#include <array>
#include <chrono>

namespace volcomp::loop {
namespace {

using namespace std::chrono_literals;
using time_point = SaturationMonitor::time_point;

constexpr auto kWarning = 200ms;
constexpr auto kFault = 500ms;

class SaturationMonitorTest : public ::testing::Test {
 protected:
  /// One evaluated cycle, 10 ms after the previous one.
  Saturation cycle(const std::array<double, 3>& targetMm) {
    now += 10ms;
    return monitor.update(now, targetMm, limits, kWarning, kFault);
  }

  SaturationMonitor monitor;
  LimiterSettings limits = LimiterSettings::uniform(0.5, 1.0);
  time_point now = time_point(std::chrono::hours(1000));
};

// Y asks for 0.8 mm with a band of 0.5 mm from the first cycle: saturated 200 ms later (the 21st
// cycle), the warning starting there once, the fault 500 ms later (the 51st).
TEST_F(SaturationMonitorTest, WarnsOnceThenFaultsAtTheThresholds) {
  int warnings = 0, firstSaturated = -1, firstFault = -1;
  for (int i = 1; i <= 60; ++i) {
    const Saturation s = cycle({0.01, 0.8, 0.0});
    EXPECT_EQ(s.axis, 1);
    EXPECT_DOUBLE_EQ(s.requestedMm, 0.8);
    if (s.warningStarted) ++warnings;
    if (firstSaturated < 0 && s.saturated) firstSaturated = i;
    if (firstFault < 0 && s.fault) firstFault = i;
  }
  EXPECT_EQ(warnings, 1);
  EXPECT_EQ(firstSaturated, 21);
  EXPECT_EQ(firstFault, 51);
}

TEST_F(SaturationMonitorTest, ATargetInsideTheBandIsNotClamped) {
  for (int i = 0; i < 100; ++i) {
    const Saturation s = cycle({0.5, -0.5, 0.49});  // on the band's edge is inside
    EXPECT_EQ(s.axis, -1);
    EXPECT_FALSE(s.saturated);
    EXPECT_FALSE(s.fault);
  }
}

TEST_F(SaturationMonitorTest, NegativeTargetsAreClampedToo) {
  Saturation s;
  for (int i = 0; i < 21; ++i) s = cycle({0.0, 0.0, -0.6});
  EXPECT_EQ(s.axis, 2);
  EXPECT_DOUBLE_EQ(s.requestedMm, -0.6);
  EXPECT_TRUE(s.saturated);
}

TEST_F(SaturationMonitorTest, ACycleInsideTheBandRestartsTheCount) {
  for (int i = 0; i < 15; ++i) cycle({0.0, 0.8, 0.0});
  cycle({0.0, 0.4, 0.0});
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(cycle({0.0, 0.8, 0.0}).saturated);
  EXPECT_TRUE(cycle({0.0, 0.8, 0.0}).saturated);
}

TEST_F(SaturationMonitorTest, ResetRestartsTheCountAndTheWarning) {
  Saturation s;
  for (int i = 0; i < 30; ++i) s = cycle({0.0, 0.8, 0.0});
  ASSERT_TRUE(s.saturated);
  monitor.reset();  // a cycle without a model evaluation
  now += 10ms;
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(cycle({0.0, 0.8, 0.0}).saturated);
  s = cycle({0.0, 0.8, 0.0});
  EXPECT_TRUE(s.saturated);
  EXPECT_TRUE(s.warningStarted);
}

// The axis held longest is named, whatever the others do; a tie goes to the higher axis.
TEST_F(SaturationMonitorTest, NamesTheAxisHeldLongest) {
  for (int i = 0; i < 5; ++i) cycle({0.7, 0.0, 0.0});
  Saturation s = cycle({0.7, 0.0, -0.9});
  EXPECT_EQ(s.axis, 0);
  EXPECT_DOUBLE_EQ(s.requestedMm, 0.7);
  for (int i = 0; i < 15; ++i) s = cycle({0.7, 0.0, -0.9});
  EXPECT_TRUE(s.saturated);
  EXPECT_TRUE(s.warningStarted);
  EXPECT_EQ(s.axis, 0);
  SaturationMonitor tie;
  const Saturation t = tie.update(now, {0.7, 0.8, 0.0}, limits, kWarning, kFault);
  EXPECT_EQ(t.axis, 1);
  EXPECT_DOUBLE_EQ(t.requestedMm, 0.8);
}

// The warning starts again after the saturation ended and came back.
TEST_F(SaturationMonitorTest, TheWarningStartsOncePerEpisode) {
  int warnings = 0;
  for (int episode = 0; episode < 3; ++episode) {
    for (int i = 0; i < 30; ++i) warnings += cycle({0.0, 0.8, 0.0}).warningStarted ? 1 : 0;
    cycle({0.0, 0.0, 0.0});
  }
  EXPECT_EQ(warnings, 3);
}

TEST_F(SaturationMonitorTest, PerAxisBands) {
  limits.axes[0].maxOffsetMm = 0.05;
  Saturation s;
  for (int i = 0; i < 21; ++i) s = cycle({0.06, 0.4, 0.0});
  EXPECT_EQ(s.axis, 0);
  EXPECT_TRUE(s.saturated);
}

TEST_F(SaturationMonitorTest, AZeroThresholdDisablesItsStage) {
  Saturation s;
  for (int i = 0; i < 200; ++i) {
    now += 10ms;
    s = monitor.update(now, {0.0, 0.8, 0.0}, limits, 0ns, kFault);
    EXPECT_FALSE(s.saturated);
    EXPECT_FALSE(s.warningStarted);
  }
  EXPECT_TRUE(s.fault);
  SaturationMonitor noFault;
  for (int i = 0; i < 200; ++i) {
    now += 10ms;
    s = noFault.update(now, {0.0, 0.8, 0.0}, limits, kWarning, 0ns);
    EXPECT_FALSE(s.fault);
  }
  EXPECT_TRUE(s.saturated);
}

}  // namespace
}  // namespace volcomp::loop
