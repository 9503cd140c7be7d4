#include "volcomp/daemon/scheduler.hpp"

#include <algorithm>
#include <utility>

namespace volcomp::daemon {

NextDeadline nextDeadline(std::chrono::steady_clock::time_point deadline,
                          std::chrono::steady_clock::time_point now,
                          std::chrono::nanoseconds period) noexcept {
  NextDeadline next{deadline + period, 0};
  if (now < next.deadline || period.count() <= 0) return next;
  const auto m = static_cast<std::uint64_t>((now - deadline) / period) + 1;
  next.deadline = deadline + static_cast<std::int64_t>(m) * period;
  next.missed = m - 1;
  return next;
}

PeriodicScheduler::PeriodicScheduler(asio::io_context& io, std::chrono::nanoseconds period,
                                     Cycle cycle)
    : timer_(io), period_(period), cycle_(std::move(cycle)) {}

void PeriodicScheduler::start() {
  running_ = true;
  deadline_ = std::chrono::steady_clock::now();
  arm();
}

void PeriodicScheduler::stop() {
  running_ = false;
  timer_.cancel();
}

void PeriodicScheduler::arm() {
  timer_.expires_at(deadline_);
  timer_.async_wait([this](const std::error_code& ec) { onTimer(ec); });
}

void PeriodicScheduler::onTimer(const std::error_code& ec) {
  if (ec || !running_) return;
  // The timer never expires early: the deadline has passed here.
  maxWakeLateness_ = std::max(
      maxWakeLateness_, std::chrono::nanoseconds(std::chrono::steady_clock::now() - deadline_));
  ++cycles_;
  if (!cycle_()) {
    running_ = false;
    return;
  }
  if (!running_) return;  // stopped from inside the cycle
  const NextDeadline next = nextDeadline(deadline_, std::chrono::steady_clock::now(), period_);
  if (next.missed > 0) {
    ++overruns_;
    missed_ += next.missed;
  }
  deadline_ = next.deadline;
  arm();
}

}  // namespace volcomp::daemon
