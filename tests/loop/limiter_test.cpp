#include "volcomp/loop/limiter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace volcomp::loop {
namespace {

constexpr double kDt = 0.01;  // 10 ms cycle

LimiterSettings settings(double maxOffset = 0.5, double maxRate = 1.0, double maxAccel = 0.0) {
  return LimiterSettings::uniform(maxOffset, maxRate, maxAccel);
}

TEST(Limiter, ClampsTargetToMaxOffset) {
  LimiterState state;
  resetLimiter(state, {0.5, -0.5, 0.0});
  const LimiterOutput out = limitStep(settings(), state, {0.8, -2.0, 0.0}, kDt);
  // Already at the band edge: the clamped target equals the state, so nothing moves.
  EXPECT_DOUBLE_EQ(out.offsetMm[0], 0.5);
  EXPECT_DOUBLE_EQ(out.offsetMm[1], -0.5);
  EXPECT_DOUBLE_EQ(out.offsetMm[2], 0.0);
  EXPECT_TRUE(out.limited);
  EXPECT_FALSE(out.invalidTarget);
}

TEST(Limiter, SlewLimitsEachStepToRateTimesDt) {
  LimiterState state;
  // max step = 1 mm/s * 0.01 s = 0.01 mm per cycle.
  const LimiterOutput out = limitStep(settings(), state, {0.3, -0.3, 0.004}, kDt);
  EXPECT_NEAR(out.offsetMm[0], 0.01, 1e-15);
  EXPECT_NEAR(out.offsetMm[1], -0.01, 1e-15);
  EXPECT_DOUBLE_EQ(out.offsetMm[2], 0.004);
  EXPECT_TRUE(out.limited);
}

TEST(Limiter, PassesTargetsWithinLimitsUnchanged) {
  LimiterState state;
  resetLimiter(state, {0.1, 0.2, -0.1});
  const LimiterOutput out = limitStep(settings(), state, {0.105, 0.195, -0.1}, kDt);
  EXPECT_DOUBLE_EQ(out.offsetMm[0], 0.105);
  EXPECT_DOUBLE_EQ(out.offsetMm[1], 0.195);
  EXPECT_DOUBLE_EQ(out.offsetMm[2], -0.1);
  EXPECT_FALSE(out.limited);
}

TEST(Limiter, AccelerationLimitBoundsVelocityChangeAndDoesNotOvershoot) {
  // a = 100 mm/s^2, v max = 10 mm/s, dt = 0.01 s: the velocity changes by at most 1 mm/s per
  // cycle, so the first step is at most 0.01 mm.
  const LimiterSettings s = settings(0.5, 10.0, 100.0);
  LimiterState state;
  double previousOffset = 0.0;
  double previousVelocity = 0.0;
  double maxSeen = 0.0;
  for (int i = 0; i < 400; ++i) {
    const LimiterOutput out = limitStep(s, state, {0.3, 0.0, 0.0}, kDt);
    const double v = (out.offsetMm[0] - previousOffset) / kDt;
    EXPECT_LE(std::abs(v - previousVelocity), 100.0 * kDt + 1e-9) << "cycle " << i;
    EXPECT_LE(std::abs(v), 10.0 + 1e-9);
    maxSeen = std::max(maxSeen, out.offsetMm[0]);
    previousOffset = out.offsetMm[0];
    previousVelocity = v;
  }
  EXPECT_DOUBLE_EQ(state.offsetMm[0], 0.3);
  EXPECT_LE(maxSeen, 0.3 + 1e-9);
}

TEST(Limiter, NanTargetIsFlaggedAndNeverOutput) {
  LimiterState state;
  resetLimiter(state, {0.2, 0.2, 0.2});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const LimiterOutput out = limitStep(settings(), state, {nan, 0.3, 0.3}, kDt);
  EXPECT_TRUE(out.invalidTarget);
  // Every axis ramps towards zero at the rate limit instead.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.offsetMm[k], 0.19, 1e-15);
}

TEST(Limiter, InfiniteTargetIsFlaggedAndNeverOutput) {
  LimiterState state;
  const double inf = std::numeric_limits<double>::infinity();
  const LimiterOutput out = limitStep(settings(), state, {0.0, -inf, 0.0}, kDt);
  EXPECT_TRUE(out.invalidTarget);
  for (double o : out.offsetMm) EXPECT_TRUE(std::isfinite(o));
}

TEST(Limiter, NonPositiveOrNanDtHoldsTheOutput) {
  LimiterState state;
  resetLimiter(state, {0.1, 0.0, 0.0});
  EXPECT_DOUBLE_EQ(limitStep(settings(), state, {0.3, 0, 0}, 0.0).offsetMm[0], 0.1);
  EXPECT_DOUBLE_EQ(
      limitStep(settings(), state, {0.3, 0, 0}, std::numeric_limits<double>::quiet_NaN())
          .offsetMm[0],
      0.1);
}

TEST(Limiter, ReadBackOutsideBandReturnsAtTheRateLimitWithoutJumping) {
  LimiterState state;
  resetLimiter(state, {0.8, 0.0, 0.0});  // controller held more than the band allows
  const LimiterOutput out = limitStep(settings(), state, {0.8, 0.0, 0.0}, kDt);
  EXPECT_NEAR(out.offsetMm[0], 0.79, 1e-15);
  EXPECT_TRUE(out.limited);
}

TEST(Limiter, NonFiniteResetValuesBecomeZero) {
  LimiterState state;
  resetLimiter(state, {std::numeric_limits<double>::quiet_NaN(), 0.1, 0.0});
  EXPECT_DOUBLE_EQ(state.offsetMm[0], 0.0);
  EXPECT_DOUBLE_EQ(state.offsetMm[1], 0.1);
}

// Property: whatever the targets (including NaN and infinities), the output is finite, stays in
// the band, and moves at most max_rate * dt per cycle; with an acceleration limit the velocity
// changes by at most max_accel * dt unless the band forces it.
TEST(Limiter, RandomTargetsNeverBreakTheLimits) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> value(-2.0, 2.0);
  std::uniform_int_distribution<int> kind(0, 19);
  for (double accel : {0.0, 50.0}) {
    const LimiterSettings s = settings(0.5, 2.0, accel);
    LimiterState state;
    std::array<double, 3> previous{};
    for (int i = 0; i < 20000; ++i) {
      std::array<double, 3> target{};
      for (double& t : target) {
        const int k = kind(rng);
        t = k == 0   ? std::numeric_limits<double>::quiet_NaN()
            : k == 1 ? std::numeric_limits<double>::infinity()
                     : value(rng);
      }
      const LimiterOutput out = limitStep(s, state, target, kDt);
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(std::isfinite(out.offsetMm[k]));
        ASSERT_LE(std::abs(out.offsetMm[k]), 0.5);
        ASSERT_LE(std::abs(out.offsetMm[k] - previous[k]), 2.0 * kDt + 1e-12);
      }
      previous = out.offsetMm;
    }
  }
}

}  // namespace
}  // namespace volcomp::loop
