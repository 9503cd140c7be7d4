#include "volcomp/daemon/scheduler.hpp"

#include <sched.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <utility>

namespace volcomp::daemon {

std::string realtimeAdvice(std::chrono::nanoseconds period, int policy) {
  if (policy == SCHED_FIFO || policy == SCHED_RR || period >= std::chrono::milliseconds(5)) {
    return {};
  }
  std::ostringstream text;
  text << "cycle " << std::chrono::duration<double, std::milli>(period).count()
       << " ms under the ordinary scheduler: expect missed deadlines (at 1 kHz about 3 x those of "
          "an empty loop); for periods this short run volcompd with real-time scheduling on a "
          "reserved core (the volcompd-realtime.conf drop-in, docs/daemon.md \"Pacing at 1 kHz\")";
  return text.str();
}

NextDeadline nextDeadline(loop::Clock::time_point deadline, loop::Clock::time_point now,
                          std::chrono::nanoseconds period) noexcept {
  NextDeadline next{deadline + period, 0};
  if (now < next.deadline || period.count() <= 0) return next;
  const auto m = static_cast<std::uint64_t>((now - deadline) / period);
  next.deadline = deadline + static_cast<std::int64_t>(m) * period;
  next.missed = m - 1;
  return next;
}

PeriodicScheduler::PeriodicScheduler(WaitableClock& clock, std::chrono::nanoseconds period,
                                     Cycle cycle)
    : clock_(clock), period_(period), cycle_(std::move(cycle)) {}

void PeriodicScheduler::start() {
  running_ = true;
  deadline_ = clock_.now();
  arm();
}

void PeriodicScheduler::stop() {
  running_ = false;
  clock_.cancel();
}

void PeriodicScheduler::runNow() {
  if (!running_) return;
  clock_.cancel();
  deadline_ = clock_.now();
  onWake();
}

void PeriodicScheduler::arm() {
  clock_.asyncWaitUntil(deadline_, [this] { onWake(); });
}

void PeriodicScheduler::onWake() {
  if (!running_) return;
  // The clock never wakes early: the deadline has passed here.
  const loop::Clock::time_point start = clock_.now();
  const std::chrono::nanoseconds lateness(start - deadline_);
  maxWakeLateness_ = std::max(maxWakeLateness_, lateness);
  if (period_.count() > 0 && lateness >= period_) ++lateStarts_;
  ++cycles_;
  if (!cycle_()) {
    running_ = false;
    return;
  }
  if (!running_) return;  // stopped from inside the cycle
  const loop::Clock::time_point end = clock_.now();
  longestCycle_ = std::max(longestCycle_, std::chrono::nanoseconds(end - start));
  const NextDeadline next = nextDeadline(deadline_, end, period_);
  if (period_.count() > 0 && end >= deadline_ + period_) {
    ++overruns_;
    missed_ += next.missed;
    // What the late wake-up alone would have skipped; the rest passed while the cycle ran.
    missedWhileRunning_ += next.missed - nextDeadline(deadline_, start, period_).missed;
  }
  deadline_ = next.deadline;
  arm();
}

}  // namespace volcomp::daemon
