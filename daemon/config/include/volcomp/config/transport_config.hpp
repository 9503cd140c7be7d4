#pragma once
/// The "transport" section of the daemon's (and the simulator's) configuration, read into the
/// settings of the driver it names: {"type": "modbus-tcp" | "modbus-rtu", ...} into
/// modbus::ModbusSettings (config/modbus_config.hpp), {"type": "can", ...} into the resolved
/// can::CanLayout (config/can_config.hpp), {"type": "linuxcnc", ...} into linuxcnc::HalSettings
/// (config/linuxcnc_config.hpp). A new transport is a new alternative here, and the compiler then
/// points at every place that must handle it.

#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "volcomp/can/layout.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/linuxcnc/settings.hpp"
#include "volcomp/modbus/settings.hpp"

namespace volcomp::config {

using TransportSettings =
    std::variant<modbus::ModbusSettings, can::CanLayout, linuxcnc::HalSettings>;

/// Parses and validates a transport section (key paths in errors start at `keyPath`); a CAN
/// section's DBC file is read relative to `file`'s folder. Throws ConfigError.
TransportSettings parseTransportSettings(const nlohmann::json& section, const std::string& file,
                                         const std::string& keyPath);

/// The section's "type": "modbus-tcp", "modbus-rtu", "can" or "linuxcnc".
std::string transportType(const TransportSettings& settings);

/// Where the transport talks to, for log lines and reports: "modbus-tcp 192.168.0.10:502",
/// "modbus-rtu /dev/ttyUSB0 (115200 8N1, slave 1)", "can can0".
std::string transportEndpoint(const TransportSettings& settings);

}  // namespace volcomp::config
