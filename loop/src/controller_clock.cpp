#include "volcomp/loop/controller_clock.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::loop {

namespace {
constexpr double kWrapTicks = 65536.0;
}

void ControllerClock::reset() noexcept {
  offsets_.reset();
  have_ = false;
  unwrappedTicks_ = 0;
}

ControllerClock::time_point ControllerClock::latchedAt(std::uint16_t ticks, double tickS,
                                                       time_point replyAt,
                                                       std::chrono::nanoseconds maxAge) noexcept {
  if (!(tickS > 0.0)) return replyAt;
  const time_point latched = map(ticks, tickS, replyAt);
  if (replyAt - latched <= maxAge) return latched;
  // Further back than any latch can be: the controller restarted its clock (or jumped it). The
  // old offsets no longer hold; this sample starts the mapping.
  reset();
  return map(ticks, tickS, replyAt);
}

ControllerClock::time_point ControllerClock::map(std::uint16_t ticks, double tickS,
                                                 time_point replyAt) noexcept {
  const double elapsedS = std::chrono::duration<double>(replyAt - lastReply_).count();
  const double wrapS = kWrapTicks * tickS;
  // A new tick size (a reload of the map) or time running backwards: start anew.
  if (have_ && (tickS != lastTickS_ || elapsedS < 0.0)) reset();
  if (!have_) {
    ++stamps_;
  } else {
    const auto step = static_cast<std::uint16_t>(ticks - lastTicks_);
    // Whole wraps between the two samples: those that bring the step nearest the elapsed time.
    const double wraps = std::max(0.0, std::round((elapsedS - step * tickS) / wrapS));
    const auto advance =
        static_cast<std::int64_t>(step) + static_cast<std::int64_t>(wraps * kWrapTicks);
    if (advance != 0) ++stamps_;
    unwrappedTicks_ += advance;
  }
  have_ = true;
  lastTicks_ = ticks;
  lastTickS_ = tickS;
  lastReply_ = replyAt;

  const auto controllerNs = std::chrono::nanoseconds(
      static_cast<std::int64_t>(std::llround(static_cast<double>(unwrappedTicks_) * tickS * 1e9)));
  offsets_.push(replyAt.time_since_epoch() - controllerNs);
  return time_point(controllerNs + offsets_.min());
}

}  // namespace volcomp::loop
