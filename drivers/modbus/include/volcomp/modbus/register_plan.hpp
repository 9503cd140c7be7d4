#pragma once
/// Where a register map puts things, in transaction terms: the block of holding registers and the
/// block of input registers that one read each covers, and the single block one write covers;
/// and the conversions between those registers and the daemon's AxisSample / OffsetCommand.
/// Shared by the driver (decode inputs, encode outputs) and the simulated controller (encode
/// inputs, decode outputs), so that both ends read the map the same way.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <system_error>

#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/codec.hpp"
#include "volcomp/modbus/registers.hpp"

namespace volcomp::modbus {

/// A contiguous range of registers of one table.
struct Block {
  std::uint16_t start = 0;
  std::uint16_t count = 0;  ///< 0 = unused
  bool contains(std::uint16_t address, int width) const noexcept {
    return address >= start && address + width <= start + count;
  }
};

struct RegisterPlan {
  Block holdingRead;  ///< all holding-register inputs (one FC03, or the read half of FC23)
  Block inputRead;    ///< all input-register inputs (one FC04)
  Block write;        ///< all outputs (one FC16, or the write half of FC23)
};

/// The blocks of a validated map (config::validateModbusRegisterMap).
RegisterPlan planRegisters(const RegisterMap& map) noexcept;

/// Registers of one table starting at protocol address `base`: a read buffer, a write buffer or
/// a whole server-side table.
struct TableView {
  std::span<std::uint16_t> registers;
  std::uint16_t base = 0;
};
struct ConstTableView {
  std::span<const std::uint16_t> registers;
  std::uint16_t base = 0;
};

/// Decodes every input of `map` into `out` (positions, enable, homed, sequence and applied
/// offsets when mapped). `holding` and `input` must cover the plan's read blocks.
/// A float register holding NaN or infinity (or a value the scale makes infinite) is decoded as
/// NaN: the loop faults on it as invalid input. Never fails.
std::error_code decodeInputs(const RegisterMap& map, ConstTableView holding, ConstTableView input,
                             loop::AxisSample& out) noexcept;

/// Encodes `command` into the output block (`holding` must cover the plan's write block).
/// Errors: Errc::value_not_finite, Errc::value_out_of_range (the view may be partly written;
/// the caller must not send it).
std::error_code encodeOutputs(const RegisterMap& map, const loop::OffsetCommand& command,
                              TableView holding) noexcept;

/// Simulator side: encodes the inputs (bits of enable/homed are set or cleared, other bits of
/// those registers kept). Values that do not fit saturate; the result says so.
std::error_code encodeInputs(const RegisterMap& map, const loop::AxisSample& sample,
                             TableView holding, TableView input) noexcept;

/// One value of the register map as it was on the wire: where it is, its registers as read or
/// written, and what they decode to (commissioning: `volcompd --probe`).
struct FieldReading {
  const char* name = "";  ///< "position.X", "enable", "offset.Z", "status", ...
  RegisterTable table = RegisterTable::Holding;
  std::uint16_t address = 0;
  int width = 1;         ///< registers
  int bit = -1;          ///< the bit of a flag, -1 for values and words
  ValueFormat format;    ///< for values (width from format.type); words are uint16
  bool isValue = false;  ///< a typed length (mm); else a flag (bit) or a plain word
  std::array<std::uint16_t, 4> registers{};  ///< the first `width` are the raw registers
  double valueMm = 0.0;                      ///< decoded length (values)
  unsigned word = 0;                         ///< the word (words) or the bit (flags)
  CodecStatus status = CodecStatus::Ok;
};

/// At most 9 inputs (3 positions, enable, homed, sequence, 3 applied offsets) and 5 outputs.
inline constexpr std::size_t kMaxFieldReadings = 9;
struct FieldReadings {
  std::array<FieldReading, kMaxFieldReadings> fields{};
  std::size_t count = 0;
};

/// Every input of `map` as read into `holding` and `input` (which must cover the plan's read
/// blocks), raw and decoded. noexcept, no allocation.
FieldReadings describeInputs(const RegisterMap& map, ConstTableView holding,
                             ConstTableView input) noexcept;

/// Every output of `map` as encoded into `holding` (which must cover the plan's write block).
FieldReadings describeOutputs(const RegisterMap& map, ConstTableView holding) noexcept;

/// Simulator side: decodes the outputs from the holding table.
std::error_code decodeOutputs(const RegisterMap& map, ConstTableView holding,
                              loop::OffsetCommand& out) noexcept;

}  // namespace volcomp::modbus
