#pragma once
/// The simulator's configuration file (volcomp-sim --config FILE):
///   {
///     "model": "vmc-850-true.json",        optional: the TRUE error model (relative to this file);
///                                          absent = a perfect machine
///     "position_semantics": "commanded" | "actual",
///     "path": {"type": "raster", "from": [x,y,z], "to": [x,y,z], "step_mm": 50, "feed_mm_min":
///     3000}
///           | {"type": "circle", "center": [x,y,z], "radius_mm": 100, "feed_mm_min": 3000}
///           | {"type": "points", "points": [[x,y,z], ...], "feed_mm_min": 3000}
///           | {"type": "csv", "file": "path.csv", "feed_mm_min": 3000},
///     "limits": {"max_offset_mm": 0.5, "max_rate_mm_s": 1.0, "rate_tolerance_ms": 5,
///                "cycle_ms": 10},                 the daemon's limiter settings and cycle period
///                                          (max_offset_mm, max_rate_mm_s: a number or
///                                          {"X": .., "Y": .., "Z": ..})
///     "heartbeat_timeout_ms": 0,           controller-side watchdog, 0 = none
///     "watchdog_ramp_mm_s": 1.0,           rate at which the watchdog removes the offsets
///     "initial_offset_mm": [0, 0, 0],      offsets applied at start (left from an earlier run)
///     "settle_ms": 0,                      statistics start this long after the first write
///     "tick_ms": 1,                        sampling period of the error statistics
///     "can_broadcast_ms": 1,               CAN, broadcast trigger: period of the input frames
///                                          (the PLC cycle; 0.1 .. 1000)
///     "transport": { the transport section, as in the daemon's configuration: "modbus-tcp",
///                    "modbus-rtu" or "can", read with the daemon's rules
///                    (config/transport_config.hpp) }
///   }
/// The limits should be the daemon's limiter settings: the simulator checks every write with them.

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/can/layout.hpp"
#include "volcomp/config/transport_config.hpp"
#include "volcomp/modbus/registers.hpp"
#include "volcomp/sim/machine.hpp"
#include "volcomp/sim/path.hpp"

namespace volcomp::sim {

struct PathSpec {
  std::string type = "circle";
  Vec3 from{}, to{};
  double stepMm = 10.0;
  Vec3 center{};
  double radiusMm = 50.0;
  std::vector<Vec3> points;
  std::string csvFile;  ///< resolved against the configuration file's directory
  double feedMmMin = 1000.0;
  double accelMmS2 = 0.0;  ///< polyline paths: exact stop at every point, this acceleration; 0 off
};

struct SimConfig {
  std::string file;
  std::optional<std::string> modelPath;  ///< resolved against the configuration file's directory
  PathSpec path;
  MachineOptions machine;
  double tickS = 0.001;
  /// The transport section read into its driver's settings (a CAN section's DBC file is read
  /// relative to the configuration file).
  config::TransportSettings transport;
  /// CAN, broadcast trigger: the input frames are sent this often (s).
  double canBroadcastS = 0.001;
};

/// Reads and parses the configuration file. Throws config::ConfigError (file, key path, what was
/// expected).
SimConfig loadSimConfig(const std::string& file);
/// Parses a configuration; `file` names it in messages and anchors relative paths (model, CSV
/// path, DBC file). The offset quantum of the limit check comes from the transport's offset
/// outputs.
SimConfig parseSimConfig(const nlohmann::json& document, const std::string& file);

/// Builds the path (a CSV path is read here; errors as std::runtime_error).
Path makePath(const PathSpec& spec);

/// One register count of each offset output in mm (0 for float registers).
Vec3 offsetQuantumMm(const modbus::RegisterMap& map) noexcept;

/// One count of each offset output signal in mm (|scale|; 0 for float signals).
Vec3 offsetQuantumMm(const can::CanLayout& layout) noexcept;

/// Travel [min, max] per axis (mm) as a model file declares it; std::nullopt = unbounded.
using Travel = std::array<std::optional<std::array<double, 2>>, 3>;

/// The true error E(q) of a 3-axis model file (and its travel, when `travel` is given).
/// Throws config::ConfigError.
ErrorFunction loadTrueError(const std::string& modelFile, Travel* travel = nullptr);

}  // namespace volcomp::sim
