// Latency compensation: the velocity estimator on its own (constant velocity, timing jitter, a
// reversal, a stop, stale samples) and the loop using it (where the model is evaluated, with a
// fake clock and a moving fake controller).
#include "volcomp/loop/latency_compensation.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

using namespace std::chrono_literals;
using model::Direction;
using time_point = VelocityEstimator::time_point;

constexpr auto kGap = 50ms;
const time_point kT0 = time_point(std::chrono::hours(10));

time_point at(double seconds) {
  return kT0 + std::chrono::duration_cast<std::chrono::nanoseconds>(
                   std::chrono::duration<double>(seconds));
}

// --- the estimator ---------------------------------------------------------------------------

TEST(VelocityEstimator, ConstantVelocityIsExactOnEveryAxis) {
  VelocityEstimator e;
  for (int i = 0; i < 6; ++i) {
    const double t = 0.01 * i;
    e.add(at(t), {100.0 + 400.0 * t, 50.0 - 100.0 * t, -20.0}, kGap);
  }
  EXPECT_EQ(e.size(), kVelocitySamples);
  EXPECT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, 400.0, 1e-6);
  EXPECT_TRUE(e.velocity(1).sure);
  EXPECT_NEAR(e.velocity(1).mmS, -100.0, 1e-6);
  EXPECT_FALSE(e.velocity(2).sure) << "an axis at rest has nothing to extrapolate";
}

TEST(VelocityEstimator, UnsureUntilThreeSamples) {
  VelocityEstimator e;
  e.add(at(0.0), {0.0, 0.0, 0.0}, kGap);
  e.add(at(0.01), {4.0, 0.0, 0.0}, kGap);
  EXPECT_FALSE(e.velocity(0).sure);
  e.add(at(0.02), {8.0, 0.0, 0.0}, kGap);
  EXPECT_TRUE(e.velocity(0).sure);
}

TEST(VelocityEstimator, MeasuredTimesAbsorbReadJitter) {
  // Reads 10 ms apart +- 3 ms, positions sampled at the measured times: the estimate is the true
  // 400 mm/s (one assuming the nominal period would be off by up to 50 %).
  VelocityEstimator e;
  const double jitter[] = {0.0, 0.003, -0.002, 0.0025, -0.003, 0.001, 0.002, -0.0015};
  for (int i = 0; i < 8; ++i) {
    const double t = 0.01 * i + jitter[i];
    e.add(at(t), {400.0 * t, 0.0, 0.0}, kGap);
    if (i >= 2) {
      ASSERT_TRUE(e.velocity(0).sure) << i;
      EXPECT_NEAR(e.velocity(0).mmS, 400.0, 1e-6) << i;
    }
  }
}

TEST(VelocityEstimator, TimestampNoiseMovesTheEstimateLittle) {
  // The controller samples up to 0.5 ms away from the measured time (its answer inside the read).
  VelocityEstimator e;
  const double offset[] = {0.0004, -0.0005, 0.0003, -0.0002, 0.0005, -0.0004, 0.0001, -0.0003};
  for (int i = 0; i < 8; ++i) {
    const double t = 0.01 * i;
    e.add(at(t), {400.0 * (t + offset[i]), 0.0, 0.0}, kGap);
    if (i >= 2) {
      ASSERT_TRUE(e.velocity(0).sure) << i;
      EXPECT_NEAR(e.velocity(0).mmS, 400.0, 0.12 * 400.0) << i;
    }
  }
}

TEST(VelocityEstimator, ReversalInTheWindowIsUnsureUntilTheWindowIsMonotonicAgain) {
  VelocityEstimator e;
  const double q[] = {0.0, 4.0, 8.0, 10.0, 6.0, 2.0, -2.0, -6.0};  // turns at 10 mm
  for (int i = 0; i < 8; ++i) {
    e.add(at(0.01 * i), {q[i], 0.0, 0.0}, kGap);
    const AxisVelocity v = e.velocity(0);
    if (i >= 2 && i <= 3) {
      EXPECT_TRUE(v.sure) << i;
      EXPECT_GT(v.mmS, 0.0) << i;
    } else if (i >= 4 && i <= 5) {
      EXPECT_FALSE(v.sure) << "the window still holds the turn at sample " << i;
    } else if (i >= 6) {
      EXPECT_TRUE(v.sure) << "the turn is the oldest sample: every step is negative";
    }
  }
  ASSERT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, -400.0, 1e-6);
}

TEST(VelocityEstimator, DecelerationTakesTheSmallerSlopeAndAStopIsUnsure) {
  VelocityEstimator e;
  const double q[] = {0.0, 4.0, 8.0, 10.0};  // 400, 400, then 200 mm/s
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {q[i], 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  EXPECT_NEAR(e.velocity(0).mmS, 200.0, 1e-6) << "the newest pair, smaller than the fit";
  e.add(at(0.04), {10.0, 0.0, 0.0}, kGap);  // stopped
  EXPECT_FALSE(e.velocity(0).sure);
}

TEST(VelocityEstimator, StaleSamplesStartANewWindowAndARepeatedTimeReplaces) {
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {4.0 * i, 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  e.add(at(0.03 + 0.2), {12.5, 0.0, 0.0}, kGap);  // 200 ms later: a pause, a link loss
  EXPECT_EQ(e.size(), 1U);
  EXPECT_FALSE(e.velocity(0).sure);
  e.add(at(0.23), {12.6, 0.0, 0.0}, kGap);  // the same instant read again
  EXPECT_EQ(e.size(), 1U);
  e.reset();
  EXPECT_EQ(e.size(), 0U);
}

TEST(PredictPositions, ExtrapolatesSureAxesWithinTheCapAndTakesTheirDirection) {
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {-400.0 * 0.01 * i, 7.0, 0.0}, kGap);
  std::array<double, 3> q{-12.0, 7.0, 0.0};
  model::Directions d{Direction::Positive, Direction::Unknown, Direction::Negative};
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.002), 1);
  EXPECT_NEAR(q[0], -12.0 - 400.0 * 0.005, 1e-9);
  EXPECT_EQ(q[1], 7.0);
  EXPECT_EQ(d[0], Direction::Negative) << "the estimate's direction";
  EXPECT_EQ(d[1], Direction::Unknown) << "unsure axes keep the tracker's";
  EXPECT_EQ(d[2], Direction::Negative);
  q = {-12.0, 7.0, 0.0};
  predictPositions(e, q, d, 500ms, 20ms, 0.002);
  EXPECT_NEAR(q[0], -12.0 - 400.0 * 0.020, 1e-9) << "the horizon is capped";
}

TEST(PredictPositions, NoiseAtRestBelowTheHysteresisIsNeitherExtrapolatedNorADirection) {
  // Four reads creeping up by 0.5 um each (encoder noise on actual positions): monotonic, so the
  // estimate is sure, but 1.5 um over the window is within the tracker's 2 um hysteresis.
  VelocityEstimator e;
  for (int i = 0; i < 4; ++i) e.add(at(0.01 * i), {10.0 + 0.0005 * i, 0.0, 0.0}, kGap);
  ASSERT_TRUE(e.velocity(0).sure);
  std::array<double, 3> q{10.0015, 0.0, 0.0};
  model::Directions d{Direction::Unknown, Direction::Unknown, Direction::Unknown};
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.002), 0);
  EXPECT_EQ(q[0], 10.0015);
  EXPECT_EQ(d[0], Direction::Unknown);
  EXPECT_EQ(predictPositions(e, q, d, 5ms, 20ms, 0.001), 1) << "beyond a smaller hysteresis";
}

// --- in the loop -----------------------------------------------------------------------------

class LatencyLoopTest : public LoopTest {
 protected:
  void SetUp() override {
    settings.latencyCompensation = true;
    settings.controllerLatency = 2ms;
    port.autoSequence = true;
    port.sample.positionMm = {100.0, 50.0, -20.0};
  }
  /// One cycle with X moving at vx mm/s (the controller samples at the cycle's clock).
  CycleReport move(double vxMmS) {
    clock.advance(settings.period);
    port.sample.positionMm[0] += vxMmS * std::chrono::duration<double>(settings.period).count();
    return loop->step();
  }
};

TEST_F(LatencyLoopTest, EvaluatesTheModelWhereTheAxisWillBeWhenTheOffsetActs) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  // Reads and writes take no time on the fake clock: h = controller latency 2 ms + half the
  // 10 ms period over which the offset holds.
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 400.0 * 0.007, 1e-6);
  EXPECT_EQ(model->lastQ[1], 50.0);
  EXPECT_EQ(model->lastDirections[0], Direction::Positive);
  EXPECT_GT(loop->counters().extrapolatedCycles, 0U);
  EXPECT_EQ(loop->state(), LoopState::Active);
}

TEST_F(LatencyLoopTest, TheMeasuredTransactionTimesLengthenTheHorizon) {
  make();
  // Each read takes 2 ms (the controller answers after 1 ms, mid-read).
  port.afterRead = [this] { clock.advance(2ms); };
  for (int i = 0; i < 10; ++i) move(100.0);
  // Cycles are now 12 ms apart: 1 mm per 12 ms. h = 1 ms (the rest of the read) + 0 (the
  // write) + 2 ms + 5 ms.
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 1.0 / 0.012 * 0.008, 1e-6);
}

TEST_F(LatencyLoopTest, OffEvaluatesAtThePositionsRead) {
  settings.latencyCompensation = false;
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
  EXPECT_EQ(loop->counters().extrapolatedCycles, 0U);
}

TEST_F(LatencyLoopTest, AReversalFallsBackToThePositionRead) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  move(-400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
  EXPECT_EQ(model->lastDirections[0], Direction::Negative) << "the tracker saw the turn";
  move(-400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]) << "the turn is still in the window";
  move(-400.0);
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] - 400.0 * 0.007, 1e-6);
}

TEST_F(LatencyLoopTest, AStopNeverTurnsTheDirection) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  for (int i = 0; i < 5; ++i) {
    move(0.0);
    EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]) << i;
    EXPECT_EQ(model->lastDirections[0], Direction::Positive) << i;
  }
}

TEST_F(LatencyLoopTest, FrozenRegistersAddNoSampleAndAPauseForgetsTheHistory) {
  make();
  for (int i = 0; i < 10; ++i) move(400.0);
  // The life counter stops: the same positions again are not a stop of the axis.
  port.autoSequence = false;
  port.sample.hasSequence = true;
  port.sample.sequence = port.sequence;
  clock.advance(settings.period);
  loop->step();
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 400.0 * 0.007, 1e-6);
  port.autoSequence = true;
  // Disabled for a while: the estimate starts again from the positions read after it.
  port.sample.enable = false;
  for (int i = 0; i < 5; ++i) move(400.0);
  port.sample.enable = true;
  move(400.0);
  EXPECT_EQ(model->lastQ[0], port.sample.positionMm[0]);
}

TEST_F(LatencyLoopTest, ExtrapolationStaysInsideTheTravel) {
  port.sample.positionMm[0] = 496.0;  // travel X [0, 500]
  make();
  for (int i = 0; i < 2; ++i) move(100.0);
  EXPECT_NEAR(model->lastQ[0], 498.0, 1e-9) << "unsure: as read";
  move(100.0);
  move(100.0);
  EXPECT_EQ(model->lastQ[0], 500.0);
  EXPECT_EQ(port.last.status & status::kOutOfTravel, 0);
}

}  // namespace
}  // namespace volcomp::loop::testing
