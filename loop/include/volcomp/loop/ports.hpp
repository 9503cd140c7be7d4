#pragma once
/// The two small ports the compensation loop depends on (read positions, write offsets), the link
/// they share, and the injected clock. Drivers (Modbus, CAN) implement them; tests use fakes.
/// Every call is noexcept and reports failures as std::error_code; none may allocate per cycle.

#include <array>
#include <chrono>
#include <cstdint>
#include <system_error>

namespace volcomp::loop {

/// One consistent read of the controller's inputs.
struct AxisSample {
  /// Axis positions in mm, machine axes X, Y, Z (already scaled and signed by the codec).
  std::array<double, 3> positionMm{};
  bool enable = false;  ///< compensation enable input
  bool homed = false;   ///< all axes homed
  /// Offsets currently applied by the controller (mm), when the installation maps a read-back.
  bool hasAppliedOffsets = false;
  std::array<double, 3> appliedOffsetMm{};
  /// The controller's life counter (a PLC cycle counter), when the installation maps one. The
  /// loop faults with "stale input" when it stops changing for longer than the stale timeout.
  bool hasSequence = false;
  std::uint16_t sequence = 0;
  /// The controller's fault acknowledge input, when the installation maps one: a rising edge
  /// clears a latched fault.
  bool hasFaultAck = false;
  bool faultAck = false;
  /// The controller's clock when it latched these positions, when the installation maps one: a
  /// 16-bit counter of `timestampTickS` seconds, wrapping (controller_clock.hpp). Latency
  /// compensation then knows the positions' age instead of taking the middle of the read.
  bool hasTimestamp = false;
  std::uint16_t timestampTicks = 0;
  double timestampTickS = 0.0;
};

/// Everything written in one transaction.
struct OffsetCommand {
  std::array<double, 3> offsetMm{};  ///< compensation offsets (mm), after the limiter
  std::uint16_t status = 0;          ///< status word (see status.hpp)
  std::uint16_t heartbeat = 0;       ///< increments every cycle
};

/// Connection to the controller. `connect` is called by the loop at start and on reconnect
/// attempts (the loop owns the backoff). Errors that mean "the link is gone" are reported by
/// read/write as std::errc::not_connected, connection_reset, broken_pipe, network_down,
/// host_unreachable, connection_aborted, connection_refused or network_unreachable (a driver
/// that sees a timeout after which the link is unusable closes it and reports not_connected);
/// the loop maps them with `isLinkError`. Any other error is a failed transaction on a live link.
class Link {
 public:
  virtual ~Link() = default;
  virtual std::error_code connect() noexcept = 0;
  virtual void disconnect() noexcept = 0;
  virtual bool connected() const noexcept = 0;
};

class PositionSource {
 public:
  virtual ~PositionSource() = default;
  /// Reads all inputs in as few transactions as possible.
  virtual std::error_code read(AxisSample& out) noexcept = 0;
};

class OffsetSink {
 public:
  virtual ~OffsetSink() = default;
  /// Writes offsets, status and heartbeat in one transaction.
  virtual std::error_code write(const OffsetCommand& command) noexcept = 0;
};

/// A controller connection: link + source + sink (what a driver provides).
class ControllerPort : public Link, public PositionSource, public OffsetSink {};

/// Monotonic clock, injected so that tests run without sleeping.
class Clock {
 public:
  using time_point = std::chrono::steady_clock::time_point;
  virtual ~Clock() = default;
  virtual time_point now() const noexcept = 0;
};

/// True for error codes that mean the transport is down (reconnect), as opposed to a failed
/// transaction on a live link (timeout, exception reply: fault, link kept).
inline bool isLinkError(std::error_code ec) noexcept {
  // Comparing with std::errc goes through the category's equivalence, so drivers' own categories
  // take part as long as they map their link failures onto these generic conditions.
  return ec == std::errc::not_connected || ec == std::errc::connection_reset ||
         ec == std::errc::broken_pipe || ec == std::errc::network_down ||
         ec == std::errc::host_unreachable || ec == std::errc::connection_aborted ||
         ec == std::errc::connection_refused || ec == std::errc::network_unreachable;
}

}  // namespace volcomp::loop
