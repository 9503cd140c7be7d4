#pragma once
/// The loop's settings in the units it computes with (durations, mm), derived from the daemon
/// configuration. See config/daemon_config.hpp for the meaning of each key.

#include <chrono>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/daemon/limiter.hpp"

namespace volcomp::daemon {

struct LoopSettings {
  /// Nominal cycle period; also the dt of the limiter (so the rate limit holds per cycle).
  std::chrono::nanoseconds period = std::chrono::milliseconds(10);
  config::PositionSemantics semantics = config::PositionSemantics::Commanded;
  LimiterSettings limiter;
  std::chrono::nanoseconds staleTimeout = std::chrono::milliseconds(500);
  bool frozenPositionsAreStale = false;
  double travelMarginMm = 1.0;
  double directionHysteresisMm = 0.002;
  /// True: starting waits for the applied offsets read back from the controller. False: they are
  /// known zero once nothing has been written for `plcZeroAfter`.
  bool offsetReadback = true;
  std::chrono::nanoseconds plcZeroAfter{0};
  std::chrono::nanoseconds reconnectInitial = std::chrono::milliseconds(100);
  std::chrono::nanoseconds reconnectMax = std::chrono::seconds(2);
  /// How long the RECONNECTED and MODEL_RELOADED status bits stay set.
  std::chrono::nanoseconds noticeHold = std::chrono::seconds(1);
};

LoopSettings loopSettingsFrom(const config::DaemonConfig& config) noexcept;

}  // namespace volcomp::daemon
