#include "volcomp/can/signal.hpp"

#include <bit>
#include <cmath>
#include <limits>

#include "volcomp/can/errors.hpp"

namespace volcomp::can {
namespace {

constexpr std::uint64_t lowMask(unsigned bits) noexcept {
  return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
}

/// Position of the signal's first bit in the "big-endian linear" numbering used for Motorola
/// signals: position p is bit 7 - p % 8 of byte p / 8, so a Motorola signal occupies the
/// consecutive positions [msb, msb + length).
constexpr unsigned motorolaLinearMsb(unsigned startBit) noexcept {
  return (startBit / 8) * 8 + (7 - startBit % 8);
}

/// Index one past the signal's last payload bit in its own numbering (Intel: LSB-first,
/// Motorola: big-endian linear).
constexpr std::size_t endPosition(const SignalSpec& spec) noexcept {
  const unsigned first =
      spec.byteOrder == ByteOrder::Intel ? spec.startBit : motorolaLinearMsb(spec.startBit);
  return std::size_t{first} + spec.length;
}

bool inPhysicalRange(const SignalSpec& spec, double physical) noexcept {
  if (!(spec.minimum < spec.maximum)) return true;
  return physical >= spec.minimum && physical <= spec.maximum;
}

}  // namespace

std::string layoutProblem(const SignalSpec& spec) {
  if (spec.length < 1 || spec.length > 64) return "length must be 1..64 bits";
  if (spec.valueType == ValueType::Float32 && spec.length != 32)
    return "a float32 signal must be 32 bits long";
  if (spec.valueType == ValueType::Float64 && spec.length != 64)
    return "a float64 signal must be 64 bits long";
  if (spec.startBit >= 8 * kFdMaxLength) return "start bit must be below 512";
  if (endPosition(spec) > 8 * kFdMaxLength) return "signal extends beyond 64 bytes";
  if (!std::isfinite(spec.scale) || spec.scale == 0.0) return "scale must be finite and non-zero";
  if (!std::isfinite(spec.offset)) return "offset must be finite";
  if (!std::isfinite(spec.minimum) || !std::isfinite(spec.maximum))
    return "minimum and maximum must be finite";
  if (!isValidId(spec.frameId, spec.extended))
    return spec.extended ? "extended identifier must be below 0x20000000"
                         : "standard identifier must be below 0x800";
  return {};
}

std::size_t bytesNeeded(const SignalSpec& spec) noexcept {
  return (endPosition(spec) + 7) / 8;
}

std::error_code decodeRaw(const SignalSpec& spec, std::span<const std::uint8_t> payload,
                          std::uint64_t& raw) noexcept {
  if (spec.length < 1 || spec.length > 64 || bytesNeeded(spec) > payload.size())
    return Errc::OutsideFrame;
  std::uint64_t value = 0;
  unsigned got = 0;
  if (spec.byteOrder == ByteOrder::Intel) {
    // Little-endian: take chunks from the LSB upwards, each chunk going above the previous ones.
    unsigned pos = spec.startBit;
    while (got < spec.length) {
      const unsigned bit = pos % 8;
      const unsigned n = std::min(8 - bit, spec.length - got);
      const std::uint64_t chunk = (payload[pos / 8] >> bit) & lowMask(n);
      value |= chunk << got;
      got += n;
      pos += n;
    }
  } else {
    // Big-endian: take chunks from the MSB downwards, shifting the previous ones up.
    unsigned pos = motorolaLinearMsb(spec.startBit);
    while (got < spec.length) {
      const unsigned fromMsb = pos % 8;
      const unsigned n = std::min(8 - fromMsb, spec.length - got);
      const std::uint64_t chunk = (payload[pos / 8] >> (8 - fromMsb - n)) & lowMask(n);
      value = (value << n) | chunk;  // n <= 8, so the shift is defined
      got += n;
      pos += n;
    }
  }
  raw = value;
  return {};
}

std::error_code encodeRaw(const SignalSpec& spec, std::uint64_t raw,
                          std::span<std::uint8_t> payload) noexcept {
  if (spec.length < 1 || spec.length > 64 || bytesNeeded(spec) > payload.size())
    return Errc::OutsideFrame;
  if ((raw & ~lowMask(spec.length)) != 0) return Errc::OutOfRange;
  unsigned put = 0;
  if (spec.byteOrder == ByteOrder::Intel) {
    unsigned pos = spec.startBit;
    while (put < spec.length) {
      const unsigned bit = pos % 8;
      const unsigned n = std::min(8 - bit, spec.length - put);
      const auto mask = static_cast<std::uint8_t>(lowMask(n) << bit);
      const auto chunk = static_cast<std::uint8_t>(((raw >> put) & lowMask(n)) << bit);
      std::uint8_t& byte = payload[pos / 8];
      byte = static_cast<std::uint8_t>((byte & ~mask) | chunk);
      put += n;
      pos += n;
    }
  } else {
    unsigned pos = motorolaLinearMsb(spec.startBit);
    while (put < spec.length) {
      const unsigned fromMsb = pos % 8;
      const unsigned n = std::min(8 - fromMsb, spec.length - put);
      const unsigned shift = 8 - fromMsb - n;
      // The next n bits below the ones already written, counted from the value's MSB.
      const std::uint64_t chunkValue = (raw >> (spec.length - put - n)) & lowMask(n);
      const auto mask = static_cast<std::uint8_t>(lowMask(n) << shift);
      const auto chunk = static_cast<std::uint8_t>(chunkValue << shift);
      std::uint8_t& byte = payload[pos / 8];
      byte = static_cast<std::uint8_t>((byte & ~mask) | chunk);
      put += n;
      pos += n;
    }
  }
  return {};
}

std::error_code decode(const SignalSpec& spec, std::span<const std::uint8_t> payload,
                       double& physical) noexcept {
  std::uint64_t raw = 0;
  if (auto ec = decodeRaw(spec, payload, raw)) return ec;
  double value = 0.0;
  switch (spec.valueType) {
    case ValueType::Unsigned:
      value = static_cast<double>(raw);
      break;
    case ValueType::Signed: {
      const bool negative = spec.length < 64 && ((raw >> (spec.length - 1)) & 1u) != 0;
      const std::uint64_t extended = negative ? (raw | ~lowMask(spec.length)) : raw;
      value = static_cast<double>(static_cast<std::int64_t>(extended));
      break;
    }
    case ValueType::Float32:
      value = static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(raw)));
      break;
    case ValueType::Float64:
      value = std::bit_cast<double>(raw);
      break;
  }
  const double result = value * spec.scale + spec.offset;
  if (!std::isfinite(result)) return Errc::NotFinite;
  if (!inPhysicalRange(spec, result)) return Errc::OutOfRange;
  physical = result;
  return {};
}

std::error_code encode(const SignalSpec& spec, double physical,
                       std::span<std::uint8_t> payload) noexcept {
  if (!std::isfinite(physical)) return Errc::NotFinite;
  if (!inPhysicalRange(spec, physical)) return Errc::OutOfRange;
  const double scaled = (physical - spec.offset) / spec.scale;
  if (!std::isfinite(scaled)) return Errc::OutOfRange;
  std::uint64_t raw = 0;
  switch (spec.valueType) {
    case ValueType::Unsigned: {
      const double rounded = std::round(scaled);
      // 2^length itself is exact in a double, so the comparison is exact at every length.
      if (rounded < 0.0 || rounded >= std::ldexp(1.0, static_cast<int>(spec.length)))
        return Errc::OutOfRange;
      raw = static_cast<std::uint64_t>(rounded);
      break;
    }
    case ValueType::Signed: {
      const double rounded = std::round(scaled);
      const double half = std::ldexp(1.0, static_cast<int>(spec.length) - 1);
      if (rounded < -half || rounded >= half) return Errc::OutOfRange;
      raw = static_cast<std::uint64_t>(static_cast<std::int64_t>(rounded)) & lowMask(spec.length);
      break;
    }
    case ValueType::Float32: {
      if (std::fabs(scaled) > static_cast<double>(std::numeric_limits<float>::max()))
        return Errc::OutOfRange;
      raw = std::bit_cast<std::uint32_t>(static_cast<float>(scaled));
      break;
    }
    case ValueType::Float64:
      raw = std::bit_cast<std::uint64_t>(scaled);
      break;
  }
  return encodeRaw(spec, raw, payload);
}

}  // namespace volcomp::can
