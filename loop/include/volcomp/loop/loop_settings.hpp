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

/// Rounding of a read-back register: one count of a 0.1 um register (mm), the default of
/// LoopSettings::readbackResolutionMm.
inline constexpr double kReadbackResolutionMm = 1e-4;

struct LoopSettings {
  /// Nominal cycle period. The limiter's dt is the measured time since the last write sent
  /// (less after a write held up on its way), capped at this period.
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
  /// Rounding of the applied-offset read-back (mm, one register count): the tolerance of the
  /// band check of a read-back and of the comparison with what the loop wrote.
  double readbackResolutionMm = kReadbackResolutionMm;
  /// Longest time from the start of a cycle's read to its write. A cycle that takes longer
  /// (stopped, starved, a slow transaction) reads again; if the second read is late too it writes
  /// nothing. A cycle that adopts a read-back (at start, after a silence of more than two
  /// periods) allows at most one period. Derived from the PLC's heartbeat timeout by the daemon.
  std::chrono::nanoseconds readToWriteMax = std::chrono::milliseconds(25);
  /// Longest stop: the ramp-out gives up after min(2 x ramp time + 1 s, this); below the
  /// service's stop timeout.
  std::chrono::nanoseconds stopTimeout = std::chrono::seconds(14);
  /// Sustained limiting: the clamp holding an axis for longer than `saturationWarning` sets
  /// SATURATED (and the daemon logs it); longer than `saturationFault` is the fault
  /// SustainedLimit. Zero disables the respective stage.
  std::chrono::nanoseconds saturationWarning = std::chrono::seconds(1);
  std::chrono::nanoseconds saturationFault = std::chrono::seconds(10);
  /// Latency compensation (latency_compensation.hpp): evaluate the model where the axes will be
  /// when the offset acts, q + v h, h = half the read transaction (the controller samples the
  /// positions mid-read) + the time to the write + half the last write transaction +
  /// `controllerLatency` + half the period (the offset then holds for a period; its middle), at
  /// most `controllerLatency` + 2 periods. Off: evaluate at the positions read.
  bool latencyCompensation = false;
  /// The controller's own delay from receiving an offset to applying it at the axes.
  std::chrono::nanoseconds controllerLatency{0};
  /// Latch every fault but a failed transaction until the controller acknowledges it.
  bool faultLatch = true;
  std::chrono::nanoseconds reconnectInitial = std::chrono::milliseconds(100);
  std::chrono::nanoseconds reconnectMax = std::chrono::seconds(2);
  /// How long the RECONNECTED and MODEL_RELOADED status bits stay set.
  std::chrono::nanoseconds noticeHold = std::chrono::seconds(1);
};

}  // namespace volcomp::loop
