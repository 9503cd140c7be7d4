#pragma once
/// Signals inside CAN frames, with the DBC conventions, and the pure codec that packs them.
///
/// Bit numbering (DBC): bit b of the payload is bit (b % 8) of byte b / 8, bit 0 being the least
/// significant bit of a byte.
/// - Intel (little-endian, DBC `@1`): `startBit` is the signal's least significant bit; raw bit i
///   is payload bit startBit + i, so a signal crossing a byte boundary continues in the next
///   byte's bit 0.
/// - Motorola (big-endian, DBC `@0`): `startBit` is the signal's most significant bit; the
///   following bits go down to bit 0 of that byte and continue at bit 7 of the next byte.
///   E.g. start 7, length 16 is a big-endian 16-bit value in bytes 0..1.
/// Values: raw is an unsigned or two's-complement signed integer of `length` bits, or the IEEE 754
/// bits of a float32 (length 32) / float64 (length 64). physical = raw * scale + offset.
/// Encoding rounds (physical - offset) / scale to the nearest integer (halves away from zero) and
/// rejects values outside the raw range or outside [minimum, maximum] (when minimum < maximum):
/// nothing wraps silently.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <system_error>

#include "volcomp/can/frame.hpp"

namespace volcomp::can {

enum class ByteOrder : std::uint8_t { Intel, Motorola };
enum class ValueType : std::uint8_t { Unsigned, Signed, Float32, Float64 };

struct SignalSpec {
  std::string name;
  std::uint32_t frameId = 0;  ///< identifier of the frame carrying the signal
  bool extended = false;      ///< 29-bit identifier
  unsigned startBit = 0;      ///< DBC start bit (LSB for Intel, MSB for Motorola)
  unsigned length = 1;        ///< bits, 1..64 (32 for Float32, 64 for Float64)
  ByteOrder byteOrder = ByteOrder::Intel;
  ValueType valueType = ValueType::Unsigned;
  double scale = 1.0;    ///< physical units per raw count (never 0)
  double offset = 0.0;   ///< physical value of raw 0
  double minimum = 0.0;  ///< physical range checked on encode and decode when minimum < maximum
  double maximum = 0.0;
  std::string unit;
  bool operator==(const SignalSpec&) const = default;
};

/// Checks the layout alone: length 1..64, float lengths, finite non-zero scale, finite offset.
/// Returns an empty string when valid, else what is wrong.
std::string layoutProblem(const SignalSpec& spec);

/// Number of payload bytes the signal needs (index of its last byte + 1).
std::size_t bytesNeeded(const SignalSpec& spec) noexcept;

/// Raw bits (zero-extended, `length` bits) of the signal in `payload`. OutsideFrame when the
/// payload is too short. noexcept and allocation-free.
std::error_code decodeRaw(const SignalSpec& spec, std::span<const std::uint8_t> payload,
                          std::uint64_t& raw) noexcept;

/// Writes the low `length` bits of `raw` into the signal's bits of `payload`, leaving the other
/// bits alone. OutsideFrame when the payload is too short; OutOfRange when `raw` has bits set
/// above `length`.
std::error_code encodeRaw(const SignalSpec& spec, std::uint64_t raw,
                          std::span<std::uint8_t> payload) noexcept;

/// Physical value of the signal in `payload`. NotFinite for a NaN/infinite float, OutOfRange when
/// outside [minimum, maximum] (when minimum < maximum).
std::error_code decode(const SignalSpec& spec, std::span<const std::uint8_t> payload,
                       double& physical) noexcept;

/// Encodes a physical value into `payload` (see the rounding and range rules above).
std::error_code encode(const SignalSpec& spec, double physical,
                       std::span<std::uint8_t> payload) noexcept;

/// Frame helpers: the payload span of a frame (its `length` bytes).
inline std::span<const std::uint8_t> payloadOf(const Frame& frame) noexcept {
  return {frame.data.data(), frame.length};
}
inline std::span<std::uint8_t> payloadOf(Frame& frame) noexcept {
  return {frame.data.data(), frame.length};
}

}  // namespace volcomp::can
