#pragma once
/// The Modbus codec's vocabulary: register tables, value types, byte orders, scale and sign, and
/// the register map of an installation (which registers hold which input or output). Plain data,
/// no I/O and no JSON, shared by the client driver, the simulated controller and any other role
/// that reads or writes the same map (config/modbus_config.hpp turns a file section into it).

#include <array>
#include <cstdint>
#include <optional>

namespace volcomp::modbus {

/// Register table: holding registers (FC03 read, FC16/FC06/FC23 write) or input registers (FC04,
/// read only).
enum class RegisterTable : std::uint8_t { Holding, Input };

/// Type of a value on the wire.
enum class RegisterType : std::uint8_t { Int16, Uint16, Int32, Uint32, Float32, Float64 };

/// Byte order of a multi-byte value across registers, naming the big-endian bytes A (most
/// significant) to D as they appear in register order: ABCD big-endian words and bytes, CDAB word
/// swap (low word first), BADC byte swap within each word, DCBA both (fully little-endian). For
/// 64-bit values the same two swaps apply to the four words; for 16-bit values only the byte swap
/// matters (ABCD = CDAB, BADC = DCBA).
enum class WordOrder : std::uint8_t { ABCD, CDAB, BADC, DCBA };

/// Protocol limits per transaction (Modbus Application Protocol v1.1b3, as libmodbus'
/// MODBUS_MAX_READ_REGISTERS, MODBUS_MAX_WRITE_REGISTERS and MODBUS_MAX_WR_WRITE_REGISTERS).
inline constexpr int kMaxReadRegisters = 125;
inline constexpr int kMaxWriteRegisters = 123;
inline constexpr int kMaxFc23WriteRegisters = 121;

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
  bool operator==(const ValueFormat&) const = default;
};

/// A typed value at a register address.
struct ValueRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  ValueFormat format;
  bool operator==(const ValueRegister&) const = default;
};

/// One bit (0 = least significant) of a 16-bit register.
struct BitRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  std::uint8_t bit = 0;
  bool operator==(const BitRegister&) const = default;
};

/// A plain 16-bit register.
struct WordRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  bool operator==(const WordRegister&) const = default;
};

/// The controller's clock when it latched the positions: one 16-bit register counting ticks of
/// `tickUs` microseconds, wrapping at 2^16 (loop::ControllerClock unwraps it).
struct TimestampRegister {
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  double tickUs = 1.0;
  bool operator==(const TimestampRegister&) const = default;
};

/// Where an installation keeps the loop's inputs and outputs. Addresses are 0-based protocol
/// addresses. The layout rules that make one read per table and one write possible are checked
/// where a map is read from a file (config::validateModbusRegisterMap).
struct RegisterMap {
  std::array<ValueRegister, 3> position{};  ///< axis positions X, Y, Z (inputs)
  BitRegister enable;                       ///< compensation enable (input)
  BitRegister homed;                        ///< all axes homed (input)
  /// Fault acknowledge (input), when mapped: a rising edge clears a latched fault.
  std::optional<BitRegister> faultAck;
  std::optional<WordRegister> sequence;  ///< controller life counter (input)
  /// When the controller latched the positions (input), when mapped.
  std::optional<TimestampRegister> timestamp;
  /// Offsets the controller currently applies (inputs), when mapped.
  std::optional<std::array<ValueRegister, 3>> appliedOffset;
  std::array<ValueRegister, 3> offset{};  ///< compensation offsets X, Y, Z (holding outputs)
  std::uint16_t statusAddress = 0;        ///< status word (holding output, uint16)
  std::uint16_t heartbeatAddress = 0;     ///< heartbeat counter (holding output, uint16)
  /// The controller implements FC23 (read/write multiple registers): the driver then writes the
  /// outputs and reads the inputs in one transaction.
  bool fc23 = false;
  bool operator==(const RegisterMap&) const = default;
};

}  // namespace volcomp::modbus
