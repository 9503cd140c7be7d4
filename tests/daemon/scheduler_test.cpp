// Absolute deadlines: the pure deadline arithmetic, then the scheduler on a real io_context
// (a busy cycle simulates an overrun; nothing sleeps).
#include "volcomp/daemon/scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <vector>

namespace volcomp::daemon {
namespace {

using namespace std::chrono_literals;
using Tp = std::chrono::steady_clock::time_point;

const Tp t0 = Tp(std::chrono::hours(10));

TEST(NextDeadline, OnTimeCycleGetsTheNextPeriod) {
  const NextDeadline n = nextDeadline(t0, t0 + 3ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 10ms);
  EXPECT_EQ(n.missed, 0u);
}

TEST(NextDeadline, LateWakeUpDoesNotShiftTheFollowingDeadlines) {
  // Woken 6 ms late and done at 9.9 ms: the next cycle is still due at 10 ms, not at 16 ms.
  const NextDeadline n = nextDeadline(t0, t0 + 9900us, 10ms);
  EXPECT_EQ(n.deadline, t0 + 10ms);
  EXPECT_EQ(n.missed, 0u);
}

TEST(NextDeadline, OverrunSkipsPastDeadlinesAndCountsThem) {
  // Ended at 25 ms: the deadlines at 10 and 20 ms are gone (2 missed), the next is 30 ms; no
  // burst of catch-up cycles.
  const NextDeadline n = nextDeadline(t0, t0 + 25ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 30ms);
  EXPECT_EQ(n.missed, 2u);
}

TEST(NextDeadline, EndingExactlyAtTheNextDeadlineCountsAsOneMissed) {
  const NextDeadline n = nextDeadline(t0, t0 + 10ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 20ms);
  EXPECT_EQ(n.missed, 1u);
}

TEST(PeriodicScheduler, RunsOnAbsoluteDeadlinesAndCountsOverruns) {
  asio::io_context io;
  constexpr auto period = 2ms;
  struct Seen {
    Tp deadline;
    Tp start;
  };
  std::vector<Seen> seen;
  seen.reserve(64);
  // The scheduler reads the clock before the cycle does: its latest start is bounded by what the
  // cycles saw.
  std::chrono::nanoseconds latestSeen{0};
  PeriodicScheduler* self = nullptr;
  PeriodicScheduler scheduler(io, period, [&] {
    seen.push_back({self->deadline(), std::chrono::steady_clock::now()});
    if (seen.size() == 5) {
      // A slow cycle: busy for 3.5 periods.
      const auto until = std::chrono::steady_clock::now() + 7ms;
      while (std::chrono::steady_clock::now() < until) {
      }
    }
    return seen.size() < 30;
  });
  self = &scheduler;
  // Guard: fail rather than hang if the schedule never ends.
  asio::steady_timer guard(io, 20s);
  bool timedOut = false;
  guard.async_wait([&](const std::error_code& ec) {
    if (!ec) {
      timedOut = true;
      io.stop();
    }
  });
  scheduler.start();
  while (scheduler.running() && !timedOut) io.run_one();
  guard.cancel();
  ASSERT_FALSE(timedOut);
  ASSERT_EQ(seen.size(), 30u);
  EXPECT_EQ(scheduler.cycles(), 30u);

  const Tp first = seen.front().deadline;
  for (std::size_t i = 0; i < seen.size(); ++i) {
    // Never early, and every deadline lies on the grid first + k * period.
    EXPECT_GE(seen[i].start, seen[i].deadline) << i;
    latestSeen = std::max(latestSeen, std::chrono::nanoseconds(seen[i].start - seen[i].deadline));
    EXPECT_EQ((seen[i].deadline - first) % period, std::chrono::nanoseconds(0)) << i;
    if (i > 0) {
      EXPECT_GT(seen[i].deadline, seen[i - 1].deadline) << i;
    }
  }
  EXPECT_GE(scheduler.maxWakeLateness(), 0ns);
  EXPECT_LE(scheduler.maxWakeLateness(), latestSeen);
  // The slow cycle made at least 3 deadlines pass: skipped and counted, not made up for.
  EXPECT_GE(scheduler.overruns(), 1u);
  EXPECT_GE(scheduler.missedDeadlines(), 3u);
  const auto gridSteps = (seen.back().deadline - first) / period;
  EXPECT_EQ(static_cast<std::uint64_t>(gridSteps), 29u + scheduler.missedDeadlines());
}

}  // namespace
}  // namespace volcomp::daemon
