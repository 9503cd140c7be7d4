#pragma once
/// The clock the daemon runs on: the loop's injected Clock, able to wait for one of its time
/// points. The scheduler reads every time (deadlines, lateness, overruns) from it and waits
/// through it, so that a test runs the daemon in simulated time (tests/daemon's SimulatedClock
/// jumps to each deadline at once) and nothing waits for real.

#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>
#include <functional>
#include <system_error>
#include <utility>

#include "volcomp/loop/ports.hpp"

namespace volcomp::daemon {

class WaitableClock : public loop::Clock {
 public:
  using Wake = std::function<void()>;
  /// Runs `wake` on the io_context's thread once now() >= deadline (at once when it has passed).
  /// One wait at a time: a new wait replaces the pending one.
  virtual void asyncWaitUntil(time_point deadline, Wake wake) = 0;
  /// Drops the pending wait: its `wake` never runs.
  virtual void cancel() noexcept = 0;
};

/// The production clock: std::chrono::steady_clock, waiting with an asio::steady_timer (which
/// never expires early) on `io`.
class SteadyWaitableClock final : public WaitableClock {
 public:
  explicit SteadyWaitableClock(asio::io_context& io) : timer_(io) {}

  time_point now() const noexcept override { return std::chrono::steady_clock::now(); }
  void asyncWaitUntil(time_point deadline, Wake wake) override {
    timer_.expires_at(deadline);
    timer_.async_wait([wake = std::move(wake)](const std::error_code& ec) {
      if (!ec) wake();
    });
  }
  void cancel() noexcept override { timer_.cancel(); }

 private:
  asio::steady_timer timer_;
};

}  // namespace volcomp::daemon
