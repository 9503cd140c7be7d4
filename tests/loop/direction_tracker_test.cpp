#include "volcomp/loop/direction_tracker.hpp"

#include <gtest/gtest.h>

namespace volcomp::loop {
namespace {

using model::Direction;

TEST(DirectionTracker, UnknownUntilTheAxisMovesMoreThanTheHysteresis) {
  DirectionTracker tracker(0.01);
  EXPECT_EQ(tracker.update({0.0, 0.0, 0.0})[0], Direction::Unknown);
  EXPECT_EQ(tracker.update({0.005, -0.005, 0.0})[0], Direction::Unknown);
  const auto& d = tracker.update({0.02, -0.02, 0.0});
  EXPECT_EQ(d[0], Direction::Positive);
  EXPECT_EQ(d[1], Direction::Negative);
  EXPECT_EQ(d[2], Direction::Unknown);
}

TEST(DirectionTracker, NoiseSmallerThanTheHysteresisDoesNotToggle) {
  DirectionTracker tracker(0.01);
  tracker.update({0.0, 0, 0});
  tracker.update({10.0, 0, 0});
  ASSERT_EQ(tracker.directions()[0], Direction::Positive);
  // Peak to peak 10.004 - 9.9941 = 0.0099 mm < h.
  for (double noise : {-0.004, 0.003, -0.004, 0.0, 0.004, -0.0059}) {
    EXPECT_EQ(tracker.update({10.0 + noise, 0, 0})[0], Direction::Positive) << noise;
  }
}

TEST(DirectionTracker, ReversalIsMeasuredFromTheExtremeReached) {
  DirectionTracker tracker(0.01);
  tracker.update({0.0, 0, 0});
  tracker.update({5.0, 0, 0});
  tracker.update({12.0, 0, 0});  // the reference follows to 12
  EXPECT_EQ(tracker.update({11.995, 0, 0})[0], Direction::Positive);
  EXPECT_EQ(tracker.update({11.985, 0, 0})[0], Direction::Negative);
  EXPECT_EQ(tracker.update({11.99, 0, 0})[0], Direction::Negative);
  EXPECT_EQ(tracker.update({12.0, 0, 0})[0], Direction::Positive);
}

TEST(DirectionTracker, ResetForgetsTheDirections) {
  DirectionTracker tracker(0.01);
  tracker.update({0.0, 0, 0});
  tracker.update({1.0, 0, 0});
  tracker.reset();
  EXPECT_EQ(tracker.directions()[0], Direction::Unknown);
  EXPECT_EQ(tracker.update({-3.0, 0, 0})[0], Direction::Unknown);
}

}  // namespace
}  // namespace volcomp::loop
