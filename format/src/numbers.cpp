#include "volcomp/format/numbers.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

namespace volcomp::format {
namespace {

// printf reads a negative precision as if none were given; fmt refuses it.
int printfPrecision(int precision) {
  return precision < 0 ? 6 : precision;
}

}  // namespace

std::string fixed(double value, int decimals) {
  return fmt::format("{:.{}f}", value, printfPrecision(decimals));
}

std::string signedFixed(double value, int decimals) {
  return fmt::format("{:+.{}f}", value, printfPrecision(decimals));
}

std::string fixedUnsignedZero(double value, int decimals) {
  std::string text = fixed(value, decimals);
  if (text.front() == '-' && text.find_first_not_of("0.", 1) == std::string::npos) text.erase(0, 1);
  return text;
}

std::string fixedSignificant(double value, int significant, int maxDecimals) {
  const int most = std::max(maxDecimals, 0);
  int decimals = most;
  // Only a finite non-zero value has a magnitude; the others print alike at any precision.
  if (std::isfinite(value) && value != 0.0) {
    decimals = std::clamp(
        significant - 1 - static_cast<int>(std::floor(std::log10(std::abs(value)))), 0, most);
  }
  return fixed(value, decimals);
}

std::string general(double value, int significant) {
  return fmt::format("{:.{}g}", value, printfPrecision(significant));
}

std::string hexId(std::uint32_t id, bool extended) {
  return extended ? fmt::format("0x{:08X}", id) : fmt::format("0x{:03X}", id);
}

std::string hexBytes(std::span<const std::uint8_t> bytes) {
  std::string text;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i > 0) text += ' ';
    fmt::format_to(std::back_inserter(text), "{:02X}", bytes[i]);
  }
  return text;
}

}  // namespace volcomp::format
