#pragma once
/// The Modbus transport section of a daemon (and simulator) configuration: the link (TCP or RTU)
/// and the register map. Plain data; the codec and the driver live in volcomp::modbus.
///
/// JSON shape (key paths relative to the section; everything not marked optional is required):
///   {
///     "type": "modbus-tcp" | "modbus-rtu",
///     "host": "127.0.0.1", "port": 502,                       (tcp)
///     "device": "/dev/ttyUSB0", "baud": 115200, "parity": "N"|"E"|"O",
///     "data_bits": 8, "stop_bits": 1,                         (rtu; baud..stop_bits optional)
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
///       "applied_offset": {"X": VALUE, "Y": VALUE, "Z": VALUE},     optional read-back
///       "offset":         {"X": VALUE, "Y": VALUE, "Z": VALUE},     outputs (holding)
///       "status": 106, "heartbeat": 107                             outputs (holding, uint16)
///     }
///   }
/// where VALUE = {"address": A, "table"?, "type"?, "order"?, "counts_per_mm"?, "sign"?} and the
/// optional fields come from "defaults". Addresses are 0-based protocol addresses.
///
/// Layout rules (validated, so that the driver reads all inputs with one FC03 and/or one FC04 and
/// writes all outputs with one FC16, as daemon spec section 1 requires):
/// - the outputs (offsets, status, heartbeat) are holding registers forming one gap-free block of
///   at most 123 registers (121 with fc23): a gap would be overwritten by the block write;
/// - the inputs of each table span at most 125 registers; with fc23 every input is a holding
///   register (FC23 reads holding registers only);
/// - no two fields overlap, except enable and homed sharing one register (different bits) and the
///   applied-offset read-back coinciding exactly with the offset outputs of the same axis;
/// - every field ends at or below address 65535.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"

namespace volcomp::config {

/// Modbus register table: holding registers (FC03 read, FC16/FC06/FC23 write) or input
/// registers (FC04, read only).
enum class RegisterTable : std::uint8_t { Holding, Input };

/// Type of a value on the wire.
enum class RegisterType : std::uint8_t { Int16, Uint16, Int32, Uint32, Float32, Float64 };

/// Byte order of a multi-byte value across registers, naming the big-endian bytes A (most
/// significant) to D as they appear in register order: ABCD big-endian words and bytes, CDAB word
/// swap (low word first), BADC byte swap within each word, DCBA both (fully little-endian). For
/// 64-bit values the same two swaps apply to the four words; for 16-bit values only the byte swap
/// matters (ABCD = CDAB, BADC = DCBA).
enum class WordOrder : std::uint8_t { ABCD, CDAB, BADC, DCBA };

/// Number of 16-bit registers a type occupies (1, 2 or 4).
constexpr int registerWidth(RegisterType type) noexcept {
  switch (type) {
    case RegisterType::Int16:
    case RegisterType::Uint16:
      return 1;
    case RegisterType::Int32:
    case RegisterType::Uint32:
    case RegisterType::Float32:
      return 2;
    case RegisterType::Float64:
      return 4;
  }
  return 1;
}

/// How a length in mm becomes a register value: raw = mm * countsPerMm * sign (rounded to the
/// nearest count, halves away from zero, for integer types), and back: mm = raw / countsPerMm *
/// sign. `sign` is +1 or -1 (the controller counts the axis the other way).
struct ValueFormat {
  RegisterType type = RegisterType::Int32;
  WordOrder order = WordOrder::ABCD;
  double countsPerMm = 10000.0;
  int sign = 1;
};

/// A typed value at a register address.
struct ValueRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  ValueFormat format;
};

/// One bit (0 = least significant) of a 16-bit register.
struct BitRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  std::uint8_t bit = 0;
};

/// A plain 16-bit register.
struct WordRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
};

struct ModbusRegisterMap {
  std::array<ValueRegister, 3> position{};  ///< axis positions X, Y, Z (inputs)
  BitRegister enable;                       ///< compensation enable (input)
  BitRegister homed;                        ///< all axes homed (input)
  std::optional<WordRegister> sequence;     ///< controller life counter (input)
  /// Offsets the controller currently applies (inputs), when mapped.
  std::optional<std::array<ValueRegister, 3>> appliedOffset;
  std::array<ValueRegister, 3> offset{};  ///< compensation offsets X, Y, Z (holding outputs)
  std::uint16_t statusAddress = 0;        ///< status word (holding output, uint16)
  std::uint16_t heartbeatAddress = 0;     ///< heartbeat counter (holding output, uint16)
  /// The controller implements FC23 (read/write multiple registers): the driver then writes the
  /// outputs and reads the inputs in one transaction.
  bool fc23 = false;
};

struct TcpLink {
  std::string host = "127.0.0.1";
  std::uint16_t port = 502;
};

struct RtuLink {
  std::string device;
  int baud = 115200;
  char parity = 'N';  ///< 'N', 'E' or 'O'
  int dataBits = 8;
  int stopBits = 1;
};

struct ModbusConfig {
  std::variant<TcpLink, RtuLink> link;
  int slaveId = 1;
  /// Maximum wait for a response to one transaction (and between bytes of a response), ms.
  double responseTimeoutMs = 50.0;
  /// This many consecutive response timeouts mean the link is gone: the driver closes it and
  /// reports not_connected, so that the loop reconnects.
  int linkLossTimeouts = 3;
  ModbusRegisterMap registers;
};

/// Parses and validates a transport section. `file` and `keyPath` (the section's own key path,
/// e.g. "transport") are used in ConfigError messages.
ModbusConfig parseModbusConfig(const nlohmann::json& section, const std::string& file,
                               const std::string& keyPath);

/// Parses and validates only a "registers" object (used by the simulator and tests).
ModbusRegisterMap parseModbusRegisterMap(const nlohmann::json& registers, const std::string& file,
                                         const std::string& keyPath);

/// Checks the layout rules above; throws ConfigError at `keyPath` when one is broken.
void validateModbusRegisterMap(const ModbusRegisterMap& map, const std::string& file,
                               const std::string& keyPath);

}  // namespace volcomp::config
