// New settings only tighten the limits of a running loop (reload_limits.hpp): the rule by itself,
// then the loop across a reload that widens (the old limits hold every write) and one that
// narrows the band below the applied offset (it slews down at the stricter rate, never jumps).
#include "volcomp/loop/reload_limits.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

constexpr double kEps = 1e-12;

TEST(ReloadLimits, EachLimitIsTheStricterOfRunningAndRequested) {
  LimiterSettings running;
  running.axes = {AxisLimits{0.1, 0.5, 0.0}, AxisLimits{0.2, 1.0, 50.0}, AxisLimits{0.3, 2.0, 0.0}};
  LimiterSettings requested;
  requested.axes = {AxisLimits{2.0, 1000.0, 10.0}, AxisLimits{0.05, 5.0, 0.0},
                    AxisLimits{0.3, 0.25, 100.0}};
  const LimiterSettings taken = stricterLimits(running, requested);
  EXPECT_EQ(taken.axes[0], (AxisLimits{0.1, 0.5, 10.0}));   // offset, rate kept; accel taken
  EXPECT_EQ(taken.axes[1], (AxisLimits{0.05, 1.0, 50.0}));  // "no accel limit" is widest
  EXPECT_EQ(taken.axes[2], (AxisLimits{0.3, 0.25, 100.0}));
}

TEST(ReloadLimits, ComparesAccelerationZeroAsNone) {
  EXPECT_EQ(compareLimit(Limit::MaxAccel, 0.0, 20.0), LimitChange::Tightened);
  EXPECT_EQ(compareLimit(Limit::MaxAccel, 20.0, 0.0), LimitChange::Widened);
  EXPECT_EQ(compareLimit(Limit::MaxAccel, 20.0, 10.0), LimitChange::Tightened);
  EXPECT_EQ(compareLimit(Limit::MaxAccel, 0.0, 0.0), LimitChange::Same);
  EXPECT_EQ(compareLimit(Limit::MaxOffset, 0.1, 0.1), LimitChange::Same);
  EXPECT_EQ(compareLimit(Limit::MaxRate, 0.5, 1000.0), LimitChange::Widened);
}

TEST(ReloadLimits, ANumberThatIsNoneIsNeverTaken) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const LimiterSettings running = LimiterSettings::uniform(0.1, 0.5, 10.0);
  EXPECT_EQ(stricterLimits(running, LimiterSettings::uniform(nan, nan, nan)), running);
  EXPECT_EQ(compareLimit(Limit::MaxRate, 0.5, nan), LimitChange::Widened);
}

class ReloadLimitsLoop : public LoopTest {
 protected:
  /// Settles on the model's offsets, then records every write from there in `writes` and gives
  /// the loop `limiter` in new settings. Returns the last write before them.
  OffsetCommand settleThenReload(const LimiterSettings& limiter) {
    make();
    runUntilSettled();
    const OffsetCommand before = port.last;
    writes.reserve(1000);
    port.history = &writes;
    LoopSettings next = settings;
    next.limiter = limiter;
    loop->setSettings(next);
    return before;
  }

  /// Every write from `from` on moves by at most maxStepMm and stays within maxOffsetMm.
  static void expectWithin(const std::vector<OffsetCommand>& writes, const OffsetCommand& from,
                           double maxOffsetMm, double maxStepMm) {
    OffsetCommand previous = from;
    for (std::size_t i = 0; i < writes.size(); ++i) {
      for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_LE(std::abs(writes[i].offsetMm[k]), maxOffsetMm + kEps) << "write " << i;
        EXPECT_LE(std::abs(writes[i].offsetMm[k] - previous.offsetMm[k]), maxStepMm + kEps)
            << "write " << i << " axis " << k;
      }
      previous = writes[i];
    }
  }

  std::vector<OffsetCommand> writes;
};

// A reload that widens 0.1 mm, 0.5 mm/s to 2 mm, 1000 mm/s with a model asking for
// 0.89 mm. The old limits hold every write: 0.005 mm per cycle up to the 0.1 mm band.
TEST_F(ReloadLimitsLoop, WiderLimitsAreNotTakenAndTheOldOnesHoldEveryWrite) {
  settings.limiter = LimiterSettings::uniform(0.1, 0.5);
  const OffsetCommand before = settleThenReload(LimiterSettings::uniform(2.0, 1000.0));
  loop->setModel(std::make_shared<FakeModel>(std::array<double, 3>{0.89, -0.5, 0.03}));
  EXPECT_EQ(loop->settings().limiter, settings.limiter);
  for (int i = 0; i < 100; ++i) cycle();
  port.history = nullptr;
  ASSERT_EQ(writes.size(), 100u);
  expectWithin(writes, before, 0.1, 0.005);
  EXPECT_DOUBLE_EQ(port.last.offsetMm[0], 0.1);  // clamped at the old band
  EXPECT_DOUBLE_EQ(port.last.offsetMm[1], -0.1);
}

// max_offset narrowed from 0.5 to 0.1 mm with 0.3 mm applied and max_rate narrowed to 0.5 mm/s:
// the offset comes down at 0.005 mm per cycle (40 cycles), without a fault and without a jump.
TEST_F(ReloadLimitsLoop, ABandNarrowedBelowTheAppliedOffsetIsReachedAtTheStricterRate) {
  model->setOffset({0.0, 0.0, 0.3});
  const OffsetCommand before = settleThenReload(LimiterSettings::uniform(0.1, 0.5));
  ASSERT_DOUBLE_EQ(before.offsetMm[2], 0.3);
  EXPECT_EQ(loop->settings().limiter, LimiterSettings::uniform(0.1, 0.5));
  int cycles = 0;
  while (port.last.offsetMm[2] > 0.1 && cycles < 1000) {
    const CycleReport r = cycle();
    EXPECT_EQ(r.fault, FaultCode::None);
    EXPECT_EQ(r.state, LoopState::Active);
    EXPECT_NE(port.last.status & status::kLimited, 0);
    ++cycles;
  }
  port.history = nullptr;
  EXPECT_EQ(cycles, 40);  // (0.3 - 0.1) / 0.005
  expectWithin(writes, before, 0.3, 0.005);
  EXPECT_NEAR(port.last.offsetMm[2], 0.1, kEps);
}

// Only the band narrows, the rate is widened: the offset still comes down at the running rate
// (0.01 mm per cycle), not at the file's 1000 mm/s.
TEST_F(ReloadLimitsLoop, ANarrowerBandWithAWiderRateSlewsAtTheRunningRate) {
  model->setOffset({0.0, 0.0, 0.3});
  const OffsetCommand before = settleThenReload(LimiterSettings::uniform(0.1, 1000.0));
  EXPECT_EQ(loop->settings().limiter, LimiterSettings::uniform(0.1, 1.0));
  for (int i = 0; i < 30; ++i) cycle();
  port.history = nullptr;
  expectWithin(writes, before, 0.3, 0.01);
  EXPECT_NEAR(writes[19].offsetMm[2], 0.1, kEps);  // (0.3 - 0.1) / 0.01 = 20 writes
}

// An acceleration limit is taken when it is new (stricter than none) and kept when the file
// removes it (none is the widest).
TEST_F(ReloadLimitsLoop, AnAccelerationLimitIsTakenButNotRemoved) {
  make();
  runUntilSettled();
  LoopSettings changed = settings;
  changed.limiter = LimiterSettings::uniform(0.5, 1.0, 20.0);
  loop->setSettings(changed);
  EXPECT_EQ(loop->settings().limiter.axes[2].maxAccelMmS2, 20.0);
  changed.limiter = LimiterSettings::uniform(0.5, 1.0, 0.0);
  loop->setSettings(changed);
  EXPECT_EQ(loop->settings().limiter.axes[2].maxAccelMmS2, 20.0);
}

}  // namespace
}  // namespace volcomp::loop::testing
