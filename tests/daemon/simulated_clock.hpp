#pragma once
// The daemon's clock in simulated time: waiting jumps the clock to the deadline at once (the wake
// is posted to the io_context), so a test runs hours of cycles in milliseconds and nothing waits
// for real. advance() stands for time a cycle itself takes.

#include <algorithm>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <chrono>
#include <cstdint>
#include <utility>

#include "volcomp/daemon/waitable_clock.hpp"

namespace volcomp::daemon::testing {

class SimulatedClock final : public WaitableClock {
 public:
  explicit SimulatedClock(asio::io_context& io) : io_(io) {}

  time_point now() const noexcept override { return now_; }
  void asyncWaitUntil(time_point deadline, Wake wake) override {
    const std::uint64_t wait = ++waits_;
    asio::post(io_, [this, deadline, wait, wake = std::move(wake)] {
      if (wait != waits_) return;  // cancelled or replaced
      now_ = std::max(now_, deadline);
      wake();
    });
  }
  void cancel() noexcept override { ++waits_; }

  void advance(std::chrono::nanoseconds d) noexcept { now_ += d; }

 private:
  asio::io_context& io_;
  time_point now_ = time_point(std::chrono::hours(1000));
  std::uint64_t waits_ = 0;
};

}  // namespace volcomp::daemon::testing
