#pragma once
/// Pure register codec: lengths in mm <-> typed values in 16-bit Modbus registers.
///
/// encode: raw = mm * countsPerMm * sign; integer types round to the nearest count (halves away
/// from zero); the bytes of raw (big-endian A, B, C, D[, E..H]) are laid into registers in the
/// configured WordOrder (see volcomp/modbus/registers.hpp). decode is the inverse:
/// mm = raw / countsPerMm * sign. Nothing allocates, nothing throws; a value that does not fit is
/// never wrapped: it is reported.

#include <cstdint>
#include <span>

#include "volcomp/modbus/registers.hpp"

namespace volcomp::modbus {

enum class CodecStatus : std::uint8_t {
  Ok,
  /// The value is outside the range of the type: the registers hold the nearest representable
  /// value (integer min/max, +-FLT_MAX).
  Saturated,
  /// NaN or infinity (encode: registers untouched; decode: the value is not a number).
  NotFinite,
};

/// Lays the low `8 * 2 * width` bits of `bits` (big-endian byte order A..) into `width` registers
/// (1, 2 or 4) in `order`.
void packBits(std::uint64_t bits, int width, WordOrder order,
              std::span<std::uint16_t> dest) noexcept;

/// Inverse of packBits.
std::uint64_t unpackBits(std::span<const std::uint16_t> src, int width, WordOrder order) noexcept;

/// Encodes `mm` into registerWidth(format.type) registers at the front of `dest`.
CodecStatus encode(double mm, const ValueFormat& format, std::span<std::uint16_t> dest) noexcept;

/// Decodes registerWidth(format.type) registers at the front of `src` into `mm`.
/// Returns NotFinite (and leaves `mm` NaN) for a NaN or infinite float on the wire, and for a
/// value the scale makes infinite (raw / countsPerMm overflowing a double).
CodecStatus decode(std::span<const std::uint16_t> src, const ValueFormat& format,
                   double& mm) noexcept;

}  // namespace volcomp::modbus
