#pragma once
/// Periodic execution on absolute deadlines (the daemon's cycle timing): cycle n is due at
/// t0 + n * period. A late wake-up does not shift later deadlines; a cycle that ends after the
/// next deadline runs the latest deadline already past at once (less than a period late) and
/// skips the older ones (they are counted, never made up for by a burst of catch-up cycles: at
/// most one cycle runs late). Time comes from the injected WaitableClock only.

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

#include "volcomp/daemon/waitable_clock.hpp"

namespace volcomp::daemon {

struct NextDeadline {
  loop::Clock::time_point deadline;
  std::uint64_t missed =
      0;  ///< deadlines skipped: a whole period or more past when the cycle ended
};

/// The deadline after `deadline` for a cycle that ended at `now`: deadline + period when that
/// is not yet past, else the latest deadline + m * period (m >= 1) not later than `now`, due at
/// once, with missed = m - 1: a deadline the cycle ran past is served late rather than dropped
/// while a cycle can still start within its period. Pure.
NextDeadline nextDeadline(loop::Clock::time_point deadline, loop::Clock::time_point now,
                          std::chrono::nanoseconds period) noexcept;

/// The warning for a cycle of `period` run under scheduling `policy` (sched_getscheduler()):
/// below 5 ms the ordinary scheduler (SCHED_OTHER, SCHED_BATCH, SCHED_IDLE) wakes the loop and its
/// peer too late too often (at 1 kHz on a shared 2-core machine: 2.7 x the missed deadlines of an
/// empty loop, docs/performance.md); empty when the policy is a real-time one or the period is
/// longer. Pure.
std::string realtimeAdvice(std::chrono::nanoseconds period, int policy);

class PeriodicScheduler {
 public:
  /// `cycle` runs once per period on the clock's io_context thread; returning false stops the
  /// schedule.
  using Cycle = std::function<bool()>;

  PeriodicScheduler(WaitableClock& clock, std::chrono::nanoseconds period, Cycle cycle);

  /// Runs the first cycle at once (as soon as the io_context runs), then one every period.
  void start();
  void stop();
  /// Runs a cycle now (an event drove it: the Modbus server's master completed a position set)
  /// and counts the next period from now, so that the timer only runs a cycle when no event came
  /// for a whole period. Ignored when not running.
  void runNow();
  bool running() const noexcept { return running_; }

  std::uint64_t cycles() const noexcept { return cycles_; }
  /// Cycles that ended after the following deadline.
  std::uint64_t overruns() const noexcept { return overruns_; }
  /// Deadlines skipped because of overruns (no cycle started within a period of them).
  std::uint64_t missedDeadlines() const noexcept { return missed_; }
  /// Of missedDeadlines(), those that a cycle taking no time would not have skipped: skipped
  /// while the cycle ran (its I/O included), not while the thread waited to be woken.
  std::uint64_t missedWhileRunning() const noexcept { return missedWhileRunning_; }
  /// The longest cycle so far, from its start to its end (I/O included).
  std::chrono::nanoseconds longestCycle() const noexcept { return longestCycle_; }
  /// Cycles that started a whole period or more after their deadline (woken that late: the
  /// measure `cyclictest` counts as wake-ups beyond one period). Together with
  /// missedDeadlines() these are the deadlines not served within one period.
  std::uint64_t lateStarts() const noexcept { return lateStarts_; }
  std::chrono::nanoseconds period() const noexcept { return period_; }
  /// The largest delay so far between a deadline and the start of its cycle: the platform's
  /// wake-up latency (timer, idle exit, the vCPU's return on a virtual machine), which an
  /// overrun includes besides the cycle's own duration.
  std::chrono::nanoseconds maxWakeLateness() const noexcept { return maxWakeLateness_; }
  /// The deadline of the cycle running now (or of the next one, between cycles).
  loop::Clock::time_point deadline() const noexcept { return deadline_; }

 private:
  void arm();
  void onWake();

  WaitableClock& clock_;
  std::chrono::nanoseconds period_;
  Cycle cycle_;
  loop::Clock::time_point deadline_{};
  std::chrono::nanoseconds maxWakeLateness_{0};
  bool running_ = false;
  std::uint64_t cycles_ = 0;
  std::uint64_t overruns_ = 0;
  std::uint64_t missed_ = 0;
  std::uint64_t lateStarts_ = 0;
  std::uint64_t missedWhileRunning_ = 0;
  std::chrono::nanoseconds longestCycle_{0};
};

}  // namespace volcomp::daemon
