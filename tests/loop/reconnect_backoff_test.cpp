// The reconnect backoff on its own: when attempts are due after a link loss and after failures.
#include "volcomp/loop/reconnect_backoff.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace volcomp::loop {
namespace {

using namespace std::chrono_literals;
using time_point = ReconnectBackoff::time_point;

constexpr auto kInitial = 100ms;
constexpr auto kMax = 2s;

const time_point kT0 = time_point(std::chrono::hours(1000));

TEST(ReconnectBackoff, AtStartAnAttemptIsDueAtOnce) {
  const ReconnectBackoff backoff;
  EXPECT_TRUE(backoff.due(kT0));
  EXPECT_EQ(backoff.wait(), 0ns);
}

TEST(ReconnectBackoff, AFailureAtStartWaitsTheInitialTime) {
  ReconnectBackoff backoff;
  backoff.attemptFailed(kT0, kInitial, kMax);
  EXPECT_EQ(backoff.wait(), kInitial);
  EXPECT_FALSE(backoff.due(kT0 + 99ms));
  EXPECT_TRUE(backoff.due(kT0 + 100ms));
}

TEST(ReconnectBackoff, TheFirstAttemptAfterALossWaitsTheInitialTime) {
  ReconnectBackoff backoff;
  backoff.linkLost(kT0, kInitial);
  EXPECT_FALSE(backoff.due(kT0));
  EXPECT_FALSE(backoff.due(kT0 + 99ms));
  EXPECT_TRUE(backoff.due(kT0 + 100ms));
  EXPECT_EQ(backoff.nextAttempt(), kT0 + 100ms);
}

// 100 ms, then 200, 400, 800, 1600, and 2 s from then on, each from the failed attempt.
TEST(ReconnectBackoff, EachFailureDoublesTheWaitUpToTheMaximum) {
  ReconnectBackoff backoff;
  backoff.linkLost(kT0, kInitial);
  time_point now = kT0 + kInitial;
  const std::chrono::milliseconds expected[] = {200ms, 400ms, 800ms, 1600ms, 2s, 2s, 2s};
  for (const auto wait : expected) {
    ASSERT_TRUE(backoff.due(now));
    backoff.attemptFailed(now, kInitial, kMax);
    EXPECT_EQ(backoff.wait(), wait);
    EXPECT_FALSE(backoff.due(now + wait - 1ns));
    now += wait;
  }
}

TEST(ReconnectBackoff, ASuccessStartsTheSequenceAnew) {
  ReconnectBackoff backoff;
  backoff.linkLost(kT0, kInitial);
  for (int i = 0; i < 4; ++i) backoff.attemptFailed(kT0, kInitial, kMax);
  backoff.connected();
  EXPECT_EQ(backoff.wait(), 0ns);
  backoff.attemptFailed(kT0 + 5s, kInitial, kMax);
  EXPECT_EQ(backoff.wait(), kInitial);
  backoff.linkLost(kT0 + 10s, kInitial);
  EXPECT_EQ(backoff.nextAttempt(), kT0 + 10s + kInitial);
}

// A maximum below the initial time: the first wait is the initial one, the next the maximum.
TEST(ReconnectBackoff, AMaximumBelowTheInitialTimeCapsFromTheSecondWait) {
  ReconnectBackoff backoff;
  backoff.linkLost(kT0, 500ms);
  EXPECT_EQ(backoff.wait(), 500ms);
  backoff.attemptFailed(kT0 + 500ms, 500ms, 300ms);
  EXPECT_EQ(backoff.wait(), 300ms);
}

}  // namespace
}  // namespace volcomp::loop
