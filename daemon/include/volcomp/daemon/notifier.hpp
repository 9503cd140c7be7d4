#pragma once
/// Service-manager notifications (sd_notify) behind a small interface, so that tests use a fake.
/// Messages are the sd_notify(3) assignments: "READY=1", "STATUS=...", "WATCHDOG=1",
/// "STOPPING=1", "RELOADING=1".

#include <chrono>
#include <optional>
#include <string_view>

namespace volcomp::daemon {

class Notifier {
 public:
  virtual ~Notifier() = default;
  /// Sends one message; failures are ignored (the service manager may not be listening).
  virtual void notify(std::string_view message) noexcept = 0;
  /// The watchdog interval the service manager expects pings within (WATCHDOG_USEC), if any.
  virtual std::optional<std::chrono::microseconds> watchdogInterval() const noexcept = 0;
};

/// libsystemd's sd_notify. Without NOTIFY_SOCKET (not run by systemd) every call does nothing.
class SystemdNotifier final : public Notifier {
 public:
  void notify(std::string_view message) noexcept override;
  std::optional<std::chrono::microseconds> watchdogInterval() const noexcept override;
};

}  // namespace volcomp::daemon
