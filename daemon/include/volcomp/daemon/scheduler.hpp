#pragma once
/// Periodic execution on absolute deadlines (daemon.md section 1): cycle n is due at
/// t0 + n * period. A late wake-up does not shift later deadlines; a cycle that ends after the
/// next deadline skips the deadlines already past (they are counted, never made up for by a burst
/// of catch-up cycles).

#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>

namespace volcomp::daemon {

struct NextDeadline {
  std::chrono::steady_clock::time_point deadline;
  std::uint64_t missed = 0;  ///< deadlines skipped because the cycle ended after them
};

/// The deadline after `deadline` for a cycle that ended at `now`: deadline + period when that
/// is still ahead, else the first deadline + m * period (m >= 2) later than `now`, with
/// missed = m - 1. Pure.
NextDeadline nextDeadline(std::chrono::steady_clock::time_point deadline,
                          std::chrono::steady_clock::time_point now,
                          std::chrono::nanoseconds period) noexcept;

class PeriodicScheduler {
 public:
  /// `cycle` runs once per period on the io_context's thread; returning false stops the schedule.
  using Cycle = std::function<bool()>;

  PeriodicScheduler(asio::io_context& io, std::chrono::nanoseconds period, Cycle cycle);

  /// Runs the first cycle at once (posted), then one every period after it.
  void start();
  void stop();
  bool running() const noexcept { return running_; }

  std::uint64_t cycles() const noexcept { return cycles_; }
  /// Cycles that ended after the following deadline.
  std::uint64_t overruns() const noexcept { return overruns_; }
  /// Deadlines skipped because of overruns.
  std::uint64_t missedDeadlines() const noexcept { return missed_; }
  std::chrono::nanoseconds period() const noexcept { return period_; }
  /// The largest delay so far between a deadline and the start of its cycle: the platform's
  /// wake-up latency (timer, idle exit, the vCPU's return on a virtual machine), which an
  /// overrun includes besides the cycle's own duration.
  std::chrono::nanoseconds maxWakeLateness() const noexcept { return maxWakeLateness_; }
  /// The deadline of the cycle running now (or of the next one, between cycles).
  std::chrono::steady_clock::time_point deadline() const noexcept { return deadline_; }

 private:
  void arm();
  void onTimer(const std::error_code& ec);

  asio::steady_timer timer_;
  std::chrono::nanoseconds period_;
  Cycle cycle_;
  std::chrono::steady_clock::time_point deadline_{};
  std::chrono::nanoseconds maxWakeLateness_{0};
  bool running_ = false;
  std::uint64_t cycles_ = 0;
  std::uint64_t overruns_ = 0;
  std::uint64_t missed_ = 0;
};

}  // namespace volcomp::daemon
