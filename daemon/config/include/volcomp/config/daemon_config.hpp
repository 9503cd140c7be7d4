#pragma once
/// The daemon configuration file (volcompd --config FILE): loop timing, limiter, safety timeouts,
/// the model to load and the transport section, read into the settings of its driver
/// (config/transport_config.hpp).
///
/// JSON shape (key paths as in error messages; required keys marked *):
///   {
///     "cycle_period_ms": 10,                 period of the cycle, ms, in [1, 1000]
///   * "position_semantics": "commanded" | "actual",
///   * "limiter": {"max_offset_mm": 0.5,      clamp band, mm, in (0, 2] (up to 100 with
///                                            "allow_max_offset_above_2mm": true)
///                 "max_rate_mm_s": 1.0,      slew limit, mm/s, in (0, 1000]
///                 "max_accel_mm_s2": 0,      optional acceleration limit, mm/s^2, 0 = none
///                                            (each of the three: a number for every axis, or
///                                            {"X": .., "Y": .., "Z": ..})
///                 "saturation_warning_ms": 1000,  clamp held this long: SATURATED + a warning
///                 "saturation_fault_ms": 10000},  ... this long: fault sustained-limit (0 = off)
///     "stop_timeout_s": 15,                  the unit's TimeoutStopSec: the ramp-out must fit
///     "accept_model_beyond_max_offset": false,  a model whose offsets exceed max_offset_mm is
///                                            refused unless this is true
///     "stale_timeout_ms": 500,               > cycle_period_ms
///     "frozen_positions_are_stale": false,   also treat unchanged positions as stale input
///     "travel_margin_mm": 1.0,               >= 0
///     "direction_hysteresis_mm": 0.002,      >= 0
///     "offset_readback": true,               the controller maps the applied offsets
///     "plc_zero_after_ms": 500,              * when offset_readback is false (see below)
///     "plc_heartbeat_timeout_ms": 50,        the PLC's heartbeat watchdog (default 5 periods)
///     "read_to_write_max_ms": 25,            default half the heartbeat timeout; a cycle slower
///                                            from its read to its write reads again
///     "fault_latch": true,                   faults (but a failed transaction) stay until the
///                                            controller acknowledges them
///     "service_watchdog_ms": 2000,           the unit's WatchdogSec (config/transport_limits.hpp)
///     "latency_compensation": {"enabled": false,        evaluate the model where the axes will be
///                              "controller_latency_ms": 0},  when the offset acts; the
///                                            controller's own delay, ms, in [0, 100]
///   * "model": "model.json",                 relative to this file's directory
///     "reconnect": {"initial_ms": 100, "max_ms": 2000},
///     "log_level": "info",                   trace|debug|info|warn|error|critical|off
///   * "transport": {"type": "modbus-tcp" | "modbus-rtu" | "can" | "linuxcnc", ...driver keys...}
///   }
/// `plc_zero_after_ms`: without a read-back the daemon only knows the applied offsets are zero
/// once its heartbeat has been silent for this long (the PLC's heartbeat timeout plus the time
/// its own ramp takes to remove the offsets); it writes nothing before that.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_plausibility.hpp"
#include "volcomp/config/transport_config.hpp"
#include "volcomp/loop/limiter.hpp"
#include "volcomp/loop/loop_settings.hpp"

namespace volcomp::config {

/// TimeoutStopSec of the installed systemd unit.
extern const double kDefaultStopTimeoutS;
/// Where the keys of the file are listed (what an unknown-key message and `volcompd --help` name).
extern const char* const kDaemonConfigKeysListedIn;
/// Largest max_offset_mm without "allow_max_offset_above_2mm": true.
inline constexpr double kMaxOffsetWithoutOverrideMm = 2.0;

struct ReconnectConfig {
  double initialMs = 100.0;
  double maxMs = 2000.0;
};

struct DaemonConfig {
  std::string file;  ///< the configuration file (messages, relative paths)
  double cyclePeriodMs = 10.0;
  loop::PositionSemantics positionSemantics = loop::PositionSemantics::Commanded;
  loop::LimiterSettings limiter;
  double staleTimeoutMs = 500.0;
  bool frozenPositionsAreStale = false;
  double travelMarginMm = 1.0;
  double directionHysteresisMm = 0.002;
  bool offsetReadback = true;
  std::optional<double> plcZeroAfterMs;
  double plcHeartbeatTimeoutMs = 50.0;
  double readToWriteMaxMs = 25.0;
  double saturationWarningMs = 1000.0;
  double saturationFaultMs = 10000.0;
  bool faultLatch = true;
  /// "latency_compensation" (loop::LoopSettings::latencyCompensation, docs/daemon.md).
  bool latencyCompensation = false;
  double controllerLatencyMs = 0.0;
  /// The service manager's watchdog interval (WatchdogSec of the installed unit, which a test
  /// compares with this default); a cycle may
  /// block on its transactions for at most half of it (config/transport_limits.hpp).
  double serviceWatchdogMs = 2000.0;
  /// The service manager's stop timeout (TimeoutStopSec of the installed unit by default); the
  /// longest stop, 2 x rampOutSeconds() + 1 s, must fit in it.
  double stopTimeoutS = kDefaultStopTimeoutS;
  /// Accept a model whose offsets exceed the limiter's max_offset somewhere in the travel (the
  /// limiter clamps them; tests of the clamp and installations that want it say so explicitly).
  bool acceptModelBeyondMaxOffset = false;
  std::string modelPath;  ///< resolved against the configuration file's directory
  ReconnectConfig reconnect;
  std::string logLevel = "info";
  /// The "transport" section, read into its driver's settings (transportType() names it).
  TransportSettings transport;
};

/// Time the limiter needs to ramp the largest allowed offset out, s: per axis max_offset /
/// max_rate, plus the acceleration and braking phases (2 x max_rate / max_accel) when an
/// acceleration limit is set; the longest axis.
double rampOutSeconds(const loop::LimiterSettings& limiter) noexcept;

/// Reads and validates a daemon configuration file. Throws ConfigError (file, key path, what was
/// expected) on any problem, including a file that cannot be read or is not JSON.
DaemonConfig loadDaemonConfig(const std::string& path);

/// Same for an already parsed document; `file` is used in messages and to resolve "model".
DaemonConfig parseDaemonConfig(const nlohmann::json& document, const std::string& file);

/// The limiter as the bound a model must fit (config/model_plausibility.hpp); std::nullopt when the
/// configuration accepts a model beyond it ("accept_model_beyond_max_offset": true).
std::optional<OffsetBound> offsetBoundOf(const DaemonConfig& config);

}  // namespace volcomp::config
