// Absolute deadlines: the pure deadline arithmetic, the scheduler in simulated time (a cycle that
// takes 3.5 periods is an overrun), and the production clock's waits on a real timer.
#include "volcomp/daemon/scheduler.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <chrono>
#include <string>
#include <vector>

#include "simulated_clock.hpp"

namespace volcomp::daemon {
namespace {

using namespace std::chrono_literals;
using Tp = loop::Clock::time_point;

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

TEST(NextDeadline, OverrunSkipsDeadlinesAPeriodPastAndServesTheLatestAtOnce) {
  // Ended at 25 ms: the deadline at 10 ms is a whole period past (1 missed); the one at 20 ms
  // is due at once, 5 ms late, within its period; the one after is 30 ms. One catch-up cycle at
  // most, never a burst.
  const NextDeadline n = nextDeadline(t0, t0 + 25ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 20ms);
  EXPECT_EQ(n.missed, 1u);
}

TEST(NextDeadline, EndingJustAfterTheNextDeadlineServesItLateWithoutSkipping) {
  const NextDeadline n = nextDeadline(t0, t0 + 10050us, 10ms);
  EXPECT_EQ(n.deadline, t0 + 10ms);
  EXPECT_EQ(n.missed, 0u);
}

TEST(NextDeadline, EndingExactlyAtTheNextDeadlineRunsItNow) {
  const NextDeadline n = nextDeadline(t0, t0 + 10ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 10ms);
  EXPECT_EQ(n.missed, 0u);
}

TEST(NextDeadline, EndingAWholePeriodAfterTheNextDeadlineSkipsIt) {
  const NextDeadline n = nextDeadline(t0, t0 + 20ms, 10ms);
  EXPECT_EQ(n.deadline, t0 + 20ms);
  EXPECT_EQ(n.missed, 1u);
}

TEST(PeriodicScheduler, RunsOnAbsoluteDeadlinesAndCountsOverruns) {
  asio::io_context io;
  testing::SimulatedClock clock(io);
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
  PeriodicScheduler scheduler(clock, period, [&] {
    seen.push_back({self->deadline(), clock.now()});
    if (seen.size() == 5) clock.advance(7ms);  // a slow cycle: 3.5 periods
    return seen.size() < 30;
  });
  self = &scheduler;
  scheduler.start();
  io.run();  // returns once the schedule has ended (nothing else is queued)
  ASSERT_EQ(seen.size(), 30u);
  EXPECT_EQ(scheduler.cycles(), 30u);
  EXPECT_FALSE(scheduler.running());

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
  // The slow cycle ran past 3 deadlines: the latest (1.5 periods after its start, half a period
  // ago) runs at once, late; the 2 before it are skipped and counted, not made up for.
  EXPECT_EQ(scheduler.overruns(), 1u);
  EXPECT_EQ(scheduler.missedDeadlines(), 2u);
  EXPECT_EQ(scheduler.missedWhileRunning(), 2u);
  EXPECT_EQ(scheduler.longestCycle(), 7ms);
  EXPECT_EQ(seen[5].deadline, seen[4].deadline + 3 * period);
  EXPECT_EQ(seen[5].start - seen[5].deadline, 1ms);
  const auto gridSteps = (seen.back().deadline - first) / period;
  EXPECT_EQ(static_cast<std::uint64_t>(gridSteps), 29u + scheduler.missedDeadlines());
}

TEST(PeriodicScheduler, CountsCyclesWokenAPeriodOrMoreLate) {
  asio::io_context io;
  testing::SimulatedClock clock(io);
  constexpr auto period = 1ms;
  int cycles = 0;
  PeriodicScheduler scheduler(clock, period, [&] {
    ++cycles;
    // The platform holds the thread before its next wake-up (queued ahead of the scheduler's
    // wait): after cycle 3 for 2.5 periods (woken 1.5 periods late: a late start; the deadline
    // half a period ago runs next, at once), after cycle 6 for 1.9 periods (woken 0.9 of a
    // period late: on time by this measure). Only the late wake-up skipped a deadline: none was
    // skipped while a cycle ran.
    if (cycles == 3) asio::post(io, [&] { clock.advance(2500us); });
    if (cycles == 6) asio::post(io, [&] { clock.advance(1900us); });
    return cycles < 10;
  });
  scheduler.start();
  io.run();
  EXPECT_EQ(scheduler.cycles(), 10u);
  EXPECT_EQ(scheduler.lateStarts(), 1u);
  EXPECT_EQ(scheduler.missedDeadlines(), 0u);
  EXPECT_EQ(scheduler.missedWhileRunning(), 0u);
  EXPECT_EQ(scheduler.maxWakeLateness(), 1500us);
}

TEST(PeriodicScheduler, StopDropsThePendingWait) {
  asio::io_context io;
  testing::SimulatedClock clock(io);
  int cycles = 0;
  PeriodicScheduler scheduler(clock, 1ms, [&] { return ++cycles < 100; });
  scheduler.start();
  io.run_one();  // the first cycle, which arms the next wait
  scheduler.stop();
  io.run();
  EXPECT_EQ(cycles, 1);
  EXPECT_FALSE(scheduler.running());
}

// The production clock waits on a real asio::steady_timer: this one needs real time (a few ms).
TEST(SteadyWaitableClock, WakesOnTheIoThreadNotBeforeTheDeadline) {
  asio::io_context io;
  SteadyWaitableClock clock(io);
  std::vector<std::chrono::nanoseconds> early;
  int wakes = 0;
  for (int i = 0; i < 3; ++i) {
    const Tp deadline = clock.now() + 1ms;
    clock.asyncWaitUntil(deadline, [&, deadline] {
      ++wakes;
      early.push_back(std::max(0ns, std::chrono::nanoseconds(deadline - clock.now())));
    });
    io.restart();
    io.run();
  }
  EXPECT_EQ(wakes, 3);
  for (auto e : early) EXPECT_EQ(e, 0ns);

  // A cancelled wait never runs its handler.
  bool woke = false;
  clock.asyncWaitUntil(clock.now() + 1ms, [&] { woke = true; });
  clock.cancel();
  io.restart();
  io.run();
  EXPECT_FALSE(woke);
}

}  // namespace
}  // namespace volcomp::daemon

namespace volcomp::daemon {
namespace {

// An event (the Modbus master's position write) runs a cycle at once and restarts the period:
// the timer's cycle that was due is dropped, the next one comes a period after the event.
TEST(PeriodicScheduler, RunNowRunsACycleAndCountsThePeriodFromIt) {
  asio::io_context io;
  testing::SimulatedClock clock(io);
  constexpr auto period = 10ms;
  std::vector<Tp> starts;
  PeriodicScheduler* self = nullptr;
  PeriodicScheduler scheduler(clock, period, [&] {
    starts.push_back(clock.now());
    if (starts.size() == 2) {
      asio::post(io, [&] {
        clock.advance(3ms);
        self->runNow();
      });
    }
    return starts.size() < 5;
  });
  self = &scheduler;
  scheduler.runNow();  // ignored before start
  EXPECT_TRUE(starts.empty());
  scheduler.start();
  io.run();
  ASSERT_EQ(starts.size(), 5u);
  EXPECT_EQ(starts[1] - starts[0], period);
  EXPECT_EQ(starts[2] - starts[1], 3ms);  // the event
  EXPECT_EQ(starts[3] - starts[2], period);
  EXPECT_EQ(starts[4] - starts[3], period);
  EXPECT_EQ(scheduler.overruns(), 0u);
}

TEST(RealtimeAdvice, ShortPeriodsUnderTheOrdinarySchedulerAreWarnedAbout) {
  const std::string advice = realtimeAdvice(1ms, SCHED_OTHER);
  EXPECT_NE(advice.find("cycle 1 ms under the ordinary scheduler"), std::string::npos) << advice;
  EXPECT_NE(advice.find("volcompd-realtime.conf"), std::string::npos) << advice;
  EXPECT_FALSE(realtimeAdvice(std::chrono::microseconds(2500), SCHED_BATCH).empty());
  EXPECT_TRUE(realtimeAdvice(1ms, SCHED_FIFO).empty());
  EXPECT_TRUE(realtimeAdvice(1ms, SCHED_RR).empty());
  EXPECT_TRUE(realtimeAdvice(5ms, SCHED_OTHER).empty()) << "the default 10 ms needs no advice";
}

}  // namespace
}  // namespace volcomp::daemon
