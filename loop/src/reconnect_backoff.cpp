#include "volcomp/loop/reconnect_backoff.hpp"

#include <algorithm>

namespace volcomp::loop {

void ReconnectBackoff::linkLost(time_point now, std::chrono::nanoseconds initial) noexcept {
  wait_ = initial;
  nextAttempt_ = now + wait_;
}

void ReconnectBackoff::attemptFailed(time_point now, std::chrono::nanoseconds initial,
                                     std::chrono::nanoseconds max) noexcept {
  wait_ = wait_.count() == 0 ? initial : std::min(2 * wait_, max);
  nextAttempt_ = now + wait_;
}

}  // namespace volcomp::loop
