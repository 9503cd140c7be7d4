#pragma once
/// The Modbus transport section of a daemon (and simulator) configuration, read into
/// modbus::ModbusSettings (the link and the register map; the vocabulary lives with the codec in
/// volcomp/modbus/registers.hpp).
///
/// JSON shape (key paths relative to the section; everything not marked optional is required):
///   {
///     "type": "modbus-tcp" | "modbus-rtu",
///     "host": "127.0.0.1", "port": 502,                       (tcp)
///     "device": "/dev/ttyUSB0", "baud": 115200, "parity": "N"|"E"|"O",
///     "data_bits": 8, "stop_bits": 1,                         (rtu; baud..stop_bits optional)
///     "role": "client" | "server",             optional, default "client"
///     "slave_id": 1,                          optional, default 1 (tcp: 255 is common)
///     "response_timeout_ms": 50,              optional, per transaction
///     "link_loss_timeouts": 3,                optional: consecutive timeouts that mean link lost
///     "registers": {
///       "fc23": false,                        optional: controller supports FC23
///       "defaults": {"table": "holding", "type": "int32", "order": "ABCD",
///                    "counts_per_mm": 10000, "sign": 1},          optional
///       "position":       {"X": VALUE, "Y": VALUE, "Z": VALUE},
///       "enable":         {"address": 12, "bit": 0, "table": "holding"},
///       "homed":          {"address": 12, "bit": 1},
///       "sequence":       {"address": 13, "table": "holding"},      optional (PLC life counter)
///       "timestamp":      {"address": 14, "tick_us": 10},           optional (when the PLC
///                         latched the positions: uint16 ticks of tick_us, wrapping)
///       "applied_offset": {"X": VALUE, "Y": VALUE, "Z": VALUE},     optional read-back
///       "offset":         {"X": VALUE, "Y": VALUE, "Z": VALUE},     outputs (holding)
///       "status": 106, "heartbeat": 107                             outputs (holding, uint16)
///     }
///   }
/// Server role (volcompd holds the bank, the controller is the master): no "host" and no
/// "link_loss_timeouts"; "port" may be 0 (any free port); optional "cycle_trigger": "write"
/// (default) | "timer"; TCP only: "listen_address" (IPv4, default "127.0.0.1"), "allowed_clients"
/// (array of IPv4 addresses, default any), "max_connections" (1..64, default 1). Every input must
/// be a holding register and an applied-offset read-back must not be the offset outputs. where
/// VALUE = {"address": A, "table"?, "type"?, "order"?, "counts_per_mm"?, "sign"?} and the optional
/// fields come from "defaults". Addresses are 0-based protocol addresses.
///
/// Layout rules (validated, so that the driver reads all inputs with one FC03 and/or one FC04 and
/// writes all outputs with one FC16, as the daemon's cycle requires):
/// - the outputs (offsets, status, heartbeat) are holding registers forming one gap-free block of
///   at most 123 registers (121 with fc23): a gap would be overwritten by the block write;
/// - the inputs of each table span at most 125 registers; with fc23 every input is a holding
///   register (FC23 reads holding registers only);
/// - no two fields overlap, except enable and homed sharing one register (different bits) and the
///   applied-offset read-back coinciding exactly with the offset outputs of the same axis;
/// - every field ends at or below address 65535.

#include <string>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/modbus/registers.hpp"
#include "volcomp/modbus/settings.hpp"

namespace volcomp::config {

/// Parses and validates a transport section. `file` and `keyPath` (the section's own key path,
/// e.g. "transport") are used in ConfigError messages.
modbus::ModbusSettings parseModbusSettings(const nlohmann::json& section, const std::string& file,
                                           const std::string& keyPath);

/// Parses and validates only a "registers" object (used by the simulator and tests).
modbus::RegisterMap parseModbusRegisterMap(const nlohmann::json& registers, const std::string& file,
                                           const std::string& keyPath);

/// Checks the layout rules above; throws ConfigError at `keyPath` when one is broken.
void validateModbusRegisterMap(const modbus::RegisterMap& map, const std::string& file,
                               const std::string& keyPath);

}  // namespace volcomp::config
