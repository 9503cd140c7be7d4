#include "volcomp/modbus/codec.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace volcomp::modbus {
namespace {

std::uint16_t swapBytes(std::uint16_t w) noexcept {
  return static_cast<std::uint16_t>((w >> 8) | (w << 8));
}

bool swapsWords(WordOrder o) noexcept {
  return o == WordOrder::CDAB || o == WordOrder::DCBA;
}
bool swapsBytes(WordOrder o) noexcept {
  return o == WordOrder::BADC || o == WordOrder::DCBA;
}

/// Clamps a finite double to [lo, hi] and rounds it to the nearest integer (halves away from
/// zero); `saturated` tells whether the clamp was needed.
template <typename Int>
Int toInteger(double x, bool& saturated) noexcept {
  const double r = std::round(x);
  constexpr auto lo = static_cast<double>(std::numeric_limits<Int>::min());
  constexpr auto hi = static_cast<double>(std::numeric_limits<Int>::max());
  saturated = r < lo || r > hi;
  if (r < lo) return std::numeric_limits<Int>::min();
  if (r > hi) return std::numeric_limits<Int>::max();
  return static_cast<Int>(r);
}

}  // namespace

void packBits(std::uint64_t bits, int width, WordOrder order,
              std::span<std::uint16_t> dest) noexcept {
  for (int i = 0; i < width; ++i) {
    // Word i in big-endian order is bits [16 * (width - 1 - i), +16).
    auto w = static_cast<std::uint16_t>(bits >> (16 * (width - 1 - i)));
    if (swapsBytes(order)) w = swapBytes(w);
    dest[static_cast<std::size_t>(swapsWords(order) ? width - 1 - i : i)] = w;
  }
}

std::uint64_t unpackBits(std::span<const std::uint16_t> src, int width, WordOrder order) noexcept {
  std::uint64_t bits = 0;
  for (int i = 0; i < width; ++i) {
    std::uint16_t w = src[static_cast<std::size_t>(swapsWords(order) ? width - 1 - i : i)];
    if (swapsBytes(order)) w = swapBytes(w);
    bits = (bits << 16) | w;
  }
  return bits;
}

CodecStatus encode(double mm, const ValueFormat& format, std::span<std::uint16_t> dest) noexcept {
  const double x = mm * format.countsPerMm * static_cast<double>(format.sign);
  if (!std::isfinite(x)) return CodecStatus::NotFinite;
  const int width = registerWidth(format.type);
  bool saturated = false;
  std::uint64_t bits = 0;
  switch (format.type) {
    case RegisterType::Int16:
      bits = static_cast<std::uint16_t>(toInteger<std::int16_t>(x, saturated));
      break;
    case RegisterType::Uint16:
      bits = toInteger<std::uint16_t>(x, saturated);
      break;
    case RegisterType::Int32:
      bits = static_cast<std::uint32_t>(toInteger<std::int32_t>(x, saturated));
      break;
    case RegisterType::Uint32:
      bits = toInteger<std::uint32_t>(x, saturated);
      break;
    case RegisterType::Float32: {
      constexpr double maxF = std::numeric_limits<float>::max();
      double clamped = x;
      if (x > maxF || x < -maxF) {
        saturated = true;
        clamped = x > 0 ? maxF : -maxF;
      }
      bits = std::bit_cast<std::uint32_t>(static_cast<float>(clamped));
      break;
    }
    case RegisterType::Float64:
      bits = std::bit_cast<std::uint64_t>(x);
      break;
  }
  packBits(bits, width, format.order, dest);
  return saturated ? CodecStatus::Saturated : CodecStatus::Ok;
}

CodecStatus decode(std::span<const std::uint16_t> src, const ValueFormat& format,
                   double& mm) noexcept {
  const int width = registerWidth(format.type);
  const std::uint64_t bits = unpackBits(src, width, format.order);
  double raw = 0.0;
  switch (format.type) {
    case RegisterType::Int16:
      raw = static_cast<std::int16_t>(static_cast<std::uint16_t>(bits));
      break;
    case RegisterType::Uint16:
      raw = static_cast<std::uint16_t>(bits);
      break;
    case RegisterType::Int32:
      raw = static_cast<std::int32_t>(static_cast<std::uint32_t>(bits));
      break;
    case RegisterType::Uint32:
      raw = static_cast<std::uint32_t>(bits);
      break;
    case RegisterType::Float32:
      raw = std::bit_cast<float>(static_cast<std::uint32_t>(bits));
      break;
    case RegisterType::Float64:
      raw = std::bit_cast<double>(bits);
      break;
  }
  // The scale can overflow a finite raw value too (any positive counts_per_mm is accepted, and
  // 1e-300 counts per mm turns every non-zero count into infinity): not finite either way.
  const double scaled = raw / format.countsPerMm * static_cast<double>(format.sign);
  if (!std::isfinite(scaled)) {
    mm = std::numeric_limits<double>::quiet_NaN();
    return CodecStatus::NotFinite;
  }
  mm = scaled;
  return CodecStatus::Ok;
}

}  // namespace volcomp::modbus
