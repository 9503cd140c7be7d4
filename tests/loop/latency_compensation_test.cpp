// Latency compensation with the fake clock: the velocity estimate (jitter, reversals) and where
// the loop evaluates the model (q + v * h, h = read time + controller latency + half a period).
#include "volcomp/loop/latency_compensation.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "loop_fixture.hpp"

namespace volcomp::loop::testing {
namespace {

using namespace std::chrono_literals;

TEST(VelocityEstimator, ConstantVelocityWithJitteredTimestampsIsEstimatedClosely) {
  // 400 mm/s on X; the read times jitter by +-1 ms around a 10 ms grid, the positions are exact
  // at the jittered times (what the controller sampled when the read arrived).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.001, 0.001);
  VelocityEstimator v;
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double t = 0.01 * i + jitter(rng);
    v.add(t, {400.0 * t, -50.0 * t, 0.0});
    if (i >= 2) {
      const auto vel = v.velocityMmS();
      worst = std::max(worst, std::abs(vel[0] - 400.0));
      EXPECT_NEAR(vel[1], -50.0, 1e-6);
      EXPECT_EQ(vel[2], 0.0);
    }
  }
  EXPECT_LT(worst, 1e-6);  // exact positions at the timestamps: the fit is exact
}

TEST(VelocityEstimator, TimestampNoiseIsDampedByTheFit) {
  // Positions sampled on the grid but stamped with +-1 ms of noise (the loop's read times): the
  // three-point fit keeps the error below the two-point difference's.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.001, 0.001);
  VelocityEstimator fit;
  double sumSqFit = 0.0, sumSqDiff = 0.0, previousT = 0.0, previousQ = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double q = 400.0 * 0.01 * i;
    const double t = 0.01 * i + jitter(rng);
    fit.add(t, {q, 0.0, 0.0});
    if (i >= 2) {
      const double e = fit.velocityMmS()[0] - 400.0;
      const double d = (q - previousQ) / (t - previousT) - 400.0;
      sumSqFit += e * e;
      sumSqDiff += d * d;
    }
    previousT = t;
    previousQ = q;
  }
  EXPECT_LT(sumSqFit, 0.6 * sumSqDiff);
}

TEST(VelocityEstimator, FollowsAReversalAtOnce) {
  VelocityEstimator v;
  v.add(0.00, {0.0, 0, 0});
  v.add(0.01, {4.0, 0, 0});
  v.add(0.02, {8.0, 0, 0});
  EXPECT_NEAR(v.velocityMmS()[0], 400.0, 1e-9);
  v.add(0.03, {4.0, 0, 0});  // reversed: the last difference alone
  EXPECT_NEAR(v.velocityMmS()[0], -400.0, 1e-9);
  v.add(0.04, {0.0, 0, 0});
  EXPECT_NEAR(v.velocityMmS()[0], -400.0, 1e-9);
}

TEST(VelocityEstimator, NeedsTwoSamplesAndSurvivesEqualTimes) {
  VelocityEstimator v;
  EXPECT_FALSE(v.valid());
  v.add(1.0, {1.0, 0, 0});
  EXPECT_FALSE(v.valid());
  v.add(1.0, {2.0, 0, 0});  // same time: replaces the sample
  EXPECT_FALSE(v.valid());
  v.add(1.01, {3.0, 0, 0});
  ASSERT_TRUE(v.valid());
  EXPECT_NEAR(v.velocityMmS()[0], 100.0, 1e-9);
  for (double x : v.velocityMmS()) EXPECT_TRUE(std::isfinite(x));
}

TEST(Extrapolate, StaysInsideTheTravelWhenTheAxisIsInside) {
  const auto q = extrapolate({495.0, 10.0, -1.0}, {400.0, -400.0, 0.0}, 0.02, {0.0, 0.0, -300.0},
                             {500.0, 400.0, 0.0});
  EXPECT_DOUBLE_EQ(q[0], 500.0);  // 503 clamped to the travel end
  EXPECT_DOUBLE_EQ(q[1], 2.0);
  EXPECT_DOUBLE_EQ(q[2], -1.0);
}

// The loop evaluates the model ahead by v * (read time + controller latency + period / 2): at
// 400 mm/s with a 10 ms period and no read time (fakes), 2 mm ahead; 3 ms of controller latency
// add 1.2 mm.
TEST_F(LoopTest, LatencyCompensationEvaluatesTheModelWhereTheAxisWillBe) {
  settings.latencyCompensation = true;
  settings.controllerLatency = 3ms;
  port.autoSequence = true;
  make();
  for (int i = 0; i < 5; ++i) {
    cycle();
    port.sample.positionMm[0] += 4.0;  // 400 mm/s
  }
  cycle();
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 400.0 * 0.008, 1e-9);
  EXPECT_NEAR(model->lastQ[1], port.sample.positionMm[1], 1e-12);
}

TEST_F(LoopTest, WithoutLatencyCompensationTheModelSeesThePositionRead) {
  make();
  for (int i = 0; i < 5; ++i) {
    cycle();
    port.sample.positionMm[0] += 4.0;
  }
  cycle();
  EXPECT_DOUBLE_EQ(model->lastQ[0], port.sample.positionMm[0]);
}

// Registers the controller did not refresh (life counter standing) are no velocity samples: the
// estimate does not collapse to zero and jump back.
TEST_F(LoopTest, LatencyCompensationSkipsUnrefreshedSamples) {
  settings.latencyCompensation = true;
  port.autoSequence = true;
  make();
  for (int i = 0; i < 5; ++i) {
    cycle();
    port.sample.positionMm[0] += 4.0;
  }
  port.autoSequence = false;  // one read of the old registers
  port.sample.hasSequence = true;
  port.sample.sequence = port.sequence;
  port.sample.positionMm[0] -= 4.0;
  cycle();
  EXPECT_NEAR(model->lastQ[0], port.sample.positionMm[0] + 2.0, 1e-9);
}

}  // namespace
}  // namespace volcomp::loop::testing
