#pragma once
/// The loop's settings in the units it computes with (durations, mm). The daemon builds them from
/// its configuration file (config/daemon_config.hpp documents each key); tests set them directly.

#include <chrono>
#include <cstdint>

#include "volcomp/loop/limiter.hpp"

namespace volcomp::loop {

/// What the controller's position registers hold, which decides where the model is evaluated.
enum class PositionSemantics : std::uint8_t {
  /// The programmed (commanded) position: evaluate the model at it.
  Commanded,
  /// The actual position, which already includes the applied offset: subtract the offset first,
  /// or the offset would feed back on itself.
  Actual,
};

struct LoopSettings {
  /// Nominal cycle period; also the dt of the limiter (so the rate limit holds per cycle).
  std::chrono::nanoseconds period = std::chrono::milliseconds(10);
  PositionSemantics semantics = PositionSemantics::Commanded;
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

}  // namespace volcomp::loop
