#pragma once
/// When the loop tries to connect again (docs/daemon.md "States", link lost; `reconnect.initial_ms`
/// and `reconnect.max_ms`). After a link loss the first attempt is due `initial` later; each failed
/// attempt doubles the wait, up to `max`:
///
///   wait_0 = initial,  wait_n+1 = min(2 * wait_n, max)     e.g. 100 ms, 200, 400, ... 2 s, 2 s
///
/// measured from the loss or the failed attempt on the loop's clock. A connection that succeeds
/// ends the sequence. Before anything was lost (at start) an attempt is due at once, and a failed
/// one waits `initial`. noexcept.

#include <chrono>

namespace volcomp::loop {

class ReconnectBackoff {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  /// True when a connection attempt may be made at `now`.
  bool due(time_point now) const noexcept { return !(now < nextAttempt_); }
  /// The link was lost at `now`: the first attempt waits `initial`.
  void linkLost(time_point now, std::chrono::nanoseconds initial) noexcept;
  /// The attempt at `now` failed: the wait doubles (`initial` after a success or at start), at
  /// most `max`.
  void attemptFailed(time_point now, std::chrono::nanoseconds initial,
                     std::chrono::nanoseconds max) noexcept;
  /// Connected: the next failure starts from `initial` again.
  void connected() noexcept { wait_ = std::chrono::nanoseconds(0); }

  /// The current wait (0 while connected or before the first failure).
  std::chrono::nanoseconds wait() const noexcept { return wait_; }
  time_point nextAttempt() const noexcept { return nextAttempt_; }

 private:
  std::chrono::nanoseconds wait_{0};
  time_point nextAttempt_{};
};

}  // namespace volcomp::loop
