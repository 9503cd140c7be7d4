// The write envelope on its own: the hull of what the controller may apply after writes with an
// unknown outcome, and the window of outputs within one limiter step of all of it.
#include "volcomp/loop/write_envelope.hpp"

#include <gtest/gtest.h>

#include <array>

namespace volcomp::loop {
namespace {

constexpr double kEps = 1e-12;
constexpr double kDtS = 0.01;  // one 10 ms period: a step of 0.01 mm at 1 mm/s

LimiterSettings limits() {
  return LimiterSettings::uniform(0.5, 1.0);
}

LimiterState at(const std::array<double, 3>& offsetMm) {
  LimiterState s;
  s.offsetMm = offsetMm;
  return s;
}

TEST(WriteEnvelope, NothingUncertainLeavesTheOutputAsItIs) {
  const WriteEnvelope envelope;
  EXPECT_FALSE(envelope.uncertain());
  LimiterState state = at({0.3, -0.2, 0.1});
  state.velocityMmS = {1.0, -1.0, 0.5};
  EXPECT_TRUE(envelope.constrain(limits(), at({0.29, -0.19, 0.095}), kDtS, state));
  EXPECT_EQ(state.offsetMm, (std::array<double, 3>{0.3, -0.2, 0.1}));
  EXPECT_EQ(state.velocityMmS, (std::array<double, 3>{1.0, -1.0, 0.5}));
}

TEST(WriteEnvelope, TheFirstUnknownOutcomeSpansFromTheValueSteppedFromToTheAttempt) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, -0.1}, {0.06, 0.0, -0.11});
  EXPECT_TRUE(envelope.uncertain());
  EXPECT_EQ(envelope.lowMm(), (std::array<double, 3>{0.05, 0.0, -0.11}));
  EXPECT_EQ(envelope.highMm(), (std::array<double, 3>{0.06, 0.0, -0.1}));
}

// Later unknown outcomes add their attempts to the hull; the value they stepped from is an
// earlier attempt, inside it already.
TEST(WriteEnvelope, LaterUnknownOutcomesGrowTheHull) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, 0.0}, {0.06, 0.0, 0.0});
  envelope.widen({0.06, 0.0, 0.0}, {0.07, 0.0, 0.0});
  envelope.widen({0.2, 0.0, 0.0}, {0.065, -0.01, 0.0});  // the first argument no longer counts
  EXPECT_DOUBLE_EQ(envelope.lowMm()[0], 0.05);
  EXPECT_DOUBLE_EQ(envelope.highMm()[0], 0.07);
  EXPECT_DOUBLE_EQ(envelope.lowMm()[1], -0.01);
  EXPECT_DOUBLE_EQ(envelope.highMm()[1], 0.0);
}

// Acknowledged 0.05, attempted 0.06: the next output must be within 0.01 of both, i.e. in
// [0.05, 0.06]. The limiter stepped on to 0.07 from the attempt; the envelope pulls it back to
// 0.06, and the velocity follows from the value stepped from.
TEST(WriteEnvelope, KeepsTheOutputWithinOneStepOfEveryValueInIt) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, 0.0}, {0.06, 0.0, 0.0});
  const LimiterState before = at({0.06, 0.0, 0.0});
  LimiterState state = at({0.07, 0.0, 0.0});
  state.velocityMmS = {1.0, 0.0, 0.0};
  ASSERT_TRUE(envelope.constrain(limits(), before, kDtS, state));
  EXPECT_NEAR(state.offsetMm[0], 0.06, kEps);
  EXPECT_NEAR(state.velocityMmS[0], 0.0, 1e-9);
  // Towards the other side: from 0.06 down to 0.05 is inside the window, kept.
  state = at({0.05, 0.0, 0.0});
  ASSERT_TRUE(envelope.constrain(limits(), before, kDtS, state));
  EXPECT_NEAR(state.offsetMm[0], 0.05, kEps);
  EXPECT_NEAR(state.velocityMmS[0], -1.0, 1e-9);
}

// Each axis with its own rate: the window of Z is twice as wide.
TEST(WriteEnvelope, TheWindowIsPerAxis) {
  LimiterSettings perAxis = limits();
  perAxis.axes[2].maxRateMmS = 2.0;
  WriteEnvelope envelope;
  envelope.widen({0.0, 0.0, 0.0}, {0.01, 0.0, 0.02});
  LimiterState state = at({0.02, 0.0, 0.04});
  ASSERT_TRUE(envelope.constrain(perAxis, at({0.01, 0.0, 0.02}), kDtS, state));
  EXPECT_NEAR(state.offsetMm[0], 0.01, kEps);  // within 0.01 of 0 and of 0.01
  EXPECT_NEAR(state.offsetMm[2], 0.02, kEps);  // within 0.02 of 0 and of 0.02
}

// A write 2 ms after the last: a step of 0.002 mm cannot reach within one step of both 0.05 and
// 0.06. Nothing may be written, and the output is left as it was.
TEST(WriteEnvelope, AnEmptyWindowRefusesAndLeavesTheOutput) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, 0.0}, {0.06, 0.0, 0.0});
  LimiterState state = at({0.062, 0.0, 0.0});
  state.velocityMmS = {1.0, 0.0, 0.0};
  EXPECT_FALSE(envelope.constrain(limits(), at({0.06, 0.0, 0.0}), 0.002, state));
  EXPECT_DOUBLE_EQ(state.offsetMm[0], 0.062);
  EXPECT_DOUBLE_EQ(state.velocityMmS[0], 1.0);
}

// Exactly half the step that made the envelope: the window is the single point between.
TEST(WriteEnvelope, AWindowOfASinglePointIsNotEmpty) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, 0.0}, {0.06, 0.0, 0.0});
  LimiterState state = at({0.065, 0.0, 0.0});
  ASSERT_TRUE(envelope.constrain(limits(), at({0.06, 0.0, 0.0}), 0.005, state));
  EXPECT_NEAR(state.offsetMm[0], 0.055, 1e-9);
}

TEST(WriteEnvelope, ClearEndsTheUncertainty) {
  WriteEnvelope envelope;
  envelope.widen({0.05, 0.0, 0.0}, {0.06, 0.0, 0.0});
  envelope.clear();
  EXPECT_FALSE(envelope.uncertain());
  LimiterState state = at({0.5, 0.0, 0.0});
  EXPECT_TRUE(envelope.constrain(limits(), at({0.0, 0.0, 0.0}), 0.001, state));
  EXPECT_DOUBLE_EQ(state.offsetMm[0], 0.5);
  // The next unknown outcome starts a new hull from the value it stepped from.
  envelope.widen({0.2, 0.0, 0.0}, {0.21, 0.0, 0.0});
  EXPECT_DOUBLE_EQ(envelope.lowMm()[0], 0.2);
  EXPECT_DOUBLE_EQ(envelope.highMm()[0], 0.21);
}

TEST(WriteEnvelope, AZeroDtGivesZeroVelocity) {
  WriteEnvelope envelope;
  envelope.widen({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  LimiterState state = at({0.0, 0.0, 0.0});
  state.velocityMmS = {0.3, 0.0, 0.0};
  ASSERT_TRUE(envelope.constrain(limits(), at({0.0, 0.0, 0.0}), 0.0, state));
  EXPECT_EQ(state.velocityMmS[0], 0.0);
}

}  // namespace
}  // namespace volcomp::loop
