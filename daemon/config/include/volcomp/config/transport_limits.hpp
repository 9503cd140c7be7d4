#pragma once
/// What a daemon configuration must satisfy between its limiter and its transport, checked when
/// the file is read (start, --check-config and every reload), each with a ConfigError naming the
/// key path:
/// (Modbus and CAN; LinuxCNC HAL pins are doubles and need neither check)
/// - every offset output and applied-offset read-back holds +-max_offset_mm of its axis (an
///   int16 at 10^6 counts/mm holds +-0.033 mm; an unsigned register holds no negative offset);
/// - the longest a cycle can block on its transactions (Modbus: transactions per cycle x
///   response_timeout_ms; CAN with the sync trigger: response_timeout_ms) is at most half the
///   service's watchdog interval (service_watchdog_ms, WatchdogSec of the installed unit), so
///   that a slow or silent controller does not get the daemon killed by its own watchdog.

#include "volcomp/config/daemon_config.hpp"

namespace volcomp::config {

/// Throws ConfigError (the configuration's file, the transport key path) when the transport
/// cannot carry the limiter's offsets or its timeouts do not fit the service watchdog.
void checkTransportLimits(const DaemonConfig& config);

/// One count of the coarsest applied-offset read-back (mm; 0 for float registers and signals,
/// and when nothing is read back): the rounding a read-back of what was written may show.
double readbackCountMm(const TransportSettings& transport) noexcept;

}  // namespace volcomp::config
