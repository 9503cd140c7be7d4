#include "volcomp/daemon/notifier.hpp"

#include <systemd/sd-daemon.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

namespace volcomp::daemon {

void SystemdNotifier::notify(std::string_view message) noexcept {
  // sd_notify wants a C string; a fixed buffer keeps the cycle's watchdog ping allocation-free.
  std::array<char, 512> buffer{};
  const std::size_t n = std::min(message.size(), buffer.size() - 1);
  std::memcpy(buffer.data(), message.data(), n);
  buffer[n] = '\0';
  (void)sd_notify(0, buffer.data());
}

std::optional<std::chrono::microseconds> SystemdNotifier::watchdogInterval() const noexcept {
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) {
    return std::chrono::microseconds(static_cast<std::int64_t>(usec));
  }
  return std::nullopt;
}

}  // namespace volcomp::daemon
