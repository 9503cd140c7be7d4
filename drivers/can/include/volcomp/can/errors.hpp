#pragma once
/// Error codes of the CAN transport (category "volcomp.can"). Link failures are not in this enum:
/// the driver reports them as std::errc::network_down / not_connected so that the daemon's
/// isLinkError() recognises them; everything here is a failed transaction on a live link (the
/// daemon faults and ramps the offsets to zero) or a codec rejection.

#include <system_error>

namespace volcomp::can {

enum class Errc {
  /// A physical value does not fit the signal (raw range of its bits, or the DBC [min|max]).
  OutOfRange = 1,
  /// A physical value (or a decoded float) is NaN or infinite.
  NotFinite,
  /// The signal's bits do not lie inside the frame (start bit + length beyond the payload).
  OutsideFrame,
  /// No complete and consistent set of input frames newer than the stale timeout (broadcast).
  StaleInput,
  /// The controller did not answer the SYNC frame within the response timeout (sync).
  NoResponse,
  /// The controller reported bus-off through an error frame: no traffic possible until restart.
  BusOff,
  /// The controller is error-passive (TX or RX error counter >= 128): the bus is unhealthy.
  ErrorPassive,
  /// The kernel's transmit queue was full (ENOBUFS/EAGAIN): the frame was dropped, not queued.
  TxDropped,
};

const std::error_category& canCategory() noexcept;
std::error_code make_error_code(Errc e) noexcept;

}  // namespace volcomp::can

template <>
struct std::is_error_code_enum<volcomp::can::Errc> : std::true_type {};
