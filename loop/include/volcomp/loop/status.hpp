#pragma once
/// The status word written to the controller with every offset command, and the fault codes.
///
/// Layout (uint16, bit 0 = least significant):
///   bit 0  ACTIVE         offsets follow the model (through the limiter)
///   bit 1  DISABLED       enable input off or axes not homed: offsets ramp to / stay at zero
///   bit 2  FAULT          a fault is present (code in bits 12..15): offsets ramp to zero
///   bit 3  LIMITED        the limiter changed at least one axis this cycle (clamp, rate, accel)
///   bit 4  RECONNECTED    the link came back less than 1 s ago (offsets continue from read-back)
///   bit 5  OUT_OF_TRAVEL  an axis is outside the model's travel (within the margin: the model is
///                         evaluated at the travel end; beyond it: FAULT with code OutOfTravel)
///   bit 6  MODEL_RELOADED a new model/config was taken over less than 1 s ago
///   bit 7  RELOAD_FAILED  the last reload was rejected; the previous model is still in use
///   bit 8  STOPPING       the daemon is shutting down: offsets ramp to zero
///   bit 9  SATURATED      the clamp (not the slew) has held an axis at its max offset for longer
///                         than the saturation warning time (the model asks for more than allowed)
///   bit 10 LATCHED        a fault is latched: it stays until the controller acknowledges it
///                         (rising edge of the fault-ack input, or the enable input switched off)
///   bit 11                reserved, always 0
///   bits 12..15           fault code (FaultCode), 0 when no fault
/// A status of 0 with zero offsets is what the daemon writes last when it stops ("inactive").

#include <cstdint>
#include <string_view>

namespace volcomp::loop {

namespace status {
inline constexpr std::uint16_t kActive = 1u << 0;
inline constexpr std::uint16_t kDisabled = 1u << 1;
inline constexpr std::uint16_t kFault = 1u << 2;
inline constexpr std::uint16_t kLimited = 1u << 3;
inline constexpr std::uint16_t kReconnected = 1u << 4;
inline constexpr std::uint16_t kOutOfTravel = 1u << 5;
inline constexpr std::uint16_t kModelReloaded = 1u << 6;
inline constexpr std::uint16_t kReloadFailed = 1u << 7;
inline constexpr std::uint16_t kStopping = 1u << 8;
inline constexpr std::uint16_t kSaturated = 1u << 9;
inline constexpr std::uint16_t kLatched = 1u << 10;
inline constexpr int kFaultCodeShift = 12;
inline constexpr std::uint16_t kFaultCodeMask = 0xF000u;
}  // namespace status

/// Why the loop is in the fault state. The numeric value is what the status word carries.
enum class FaultCode : std::uint8_t {
  None = 0,
  /// The controller's life counter (or, when configured, the positions) did not change for longer
  /// than the stale timeout.
  StaleInput = 1,
  /// An axis is outside the model's travel by more than the travel margin.
  OutOfTravel = 2,
  /// A position or read-back offset is NaN or infinite.
  InvalidInput = 3,
  /// The model returned a NaN or infinite offset.
  ModelInvalid = 4,
  /// The offset solve p(q + o) = p0(q) did not converge.
  NotConverged = 5,
  /// A read or write transaction failed on a live link (timeout, exception reply).
  TransactionError = 6,
  /// The clamp held an axis at its max offset for longer than the saturation fault time.
  SustainedLimit = 7,
  /// The controller reports applied offsets outside +-max_offset: nothing is written while it
  /// does (the controller's own heartbeat watchdog removes them).
  ReadbackOutOfRange = 8,
};

/// True for faults that the fault latch holds until acknowledged: every fault except a failed
/// transaction (a transport fault clears once the controller answers again).
constexpr bool latchable(FaultCode code) noexcept {
  return code != FaultCode::None && code != FaultCode::TransactionError;
}

/// Stable lower-case name, e.g. "stale-input" ("none" for None).
std::string_view faultName(FaultCode code) noexcept;

constexpr std::uint16_t withFaultCode(std::uint16_t word, FaultCode code) noexcept {
  return static_cast<std::uint16_t>((word & ~status::kFaultCodeMask) |
                                    (static_cast<unsigned>(code) << status::kFaultCodeShift));
}

constexpr FaultCode faultCodeOf(std::uint16_t word) noexcept {
  return static_cast<FaultCode>((word & status::kFaultCodeMask) >> status::kFaultCodeShift);
}

}  // namespace volcomp::loop
