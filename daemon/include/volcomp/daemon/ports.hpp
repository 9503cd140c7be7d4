#pragma once
/// The two small ports the compensation loop depends on (read positions, write offsets), the link
/// they share, and the injected clock. Drivers (Modbus, CAN) implement them; tests use fakes.
/// Every call is noexcept and reports failures as std::error_code; none may allocate per cycle.

#include <array>
#include <chrono>
#include <cstdint>
#include <system_error>

namespace volcomp::daemon {

/// One consistent read of the controller's inputs.
struct AxisSample {
  /// Axis positions in mm, machine axes X, Y, Z (already scaled and signed by the codec).
  std::array<double, 3> positionMm{};
  bool enable = false;  ///< compensation enable input
  bool homed = false;   ///< all axes homed
  /// Offsets currently applied by the controller (mm), when the installation maps a read-back.
  bool hasAppliedOffsets = false;
  std::array<double, 3> appliedOffsetMm{};
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
/// host_unreachable or timed_out-after-disconnect; the loop maps them with `isLinkError`.
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
bool isLinkError(std::error_code ec) noexcept;

}  // namespace volcomp::daemon
