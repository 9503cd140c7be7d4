#include "volcomp/nc/numbers.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace volcomp::nc {

bool scanNumber(std::string_view line, std::size_t& pos, double& value,
                bool blanksInside) noexcept {
  // Collect the characters of the number without the blanks LinuxCNC ignores, then convert.
  std::array<char, 64> text{};
  std::size_t n = 0;
  std::size_t i = pos;
  const auto skipBlanks = [&] {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  };
  skipBlanks();
  bool negative = false;
  if (i < line.size() && (line[i] == '+' || line[i] == '-')) {
    negative = line[i] == '-';
    ++i;
    if (blanksInside) skipBlanks();
  }
  bool digits = false;
  bool point = false;
  std::size_t end = i;
  while (i < line.size()) {
    const char c = line[i];
    if (c >= '0' && c <= '9') {
      digits = true;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      break;
    }
    if (n + 1 >= text.size()) return false;
    text[n++] = c;
    ++i;
    end = i;
    if (blanksInside) skipBlanks();
  }
  if (!digits) return false;
  double parsed = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + n, parsed);
  if (result.ec != std::errc() || result.ptr != text.data() + n) return false;
  value = negative ? -parsed : parsed;
  pos = end;
  return true;
}

double pow10(int decimals) noexcept {
  static constexpr std::array<double, 10> powers{1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  return powers[static_cast<std::size_t>(decimals)];
}

void appendCounts(std::string& out, std::int64_t counts, int decimals) {
  std::array<char, 32> digits{};
  const bool negative = counts < 0;
  const std::uint64_t magnitude =
      negative ? 0u - static_cast<std::uint64_t>(counts) : static_cast<std::uint64_t>(counts);
  const auto result = std::to_chars(digits.data(), digits.data() + digits.size(), magnitude);
  auto length = static_cast<int>(result.ptr - digits.data());
  // Trailing zeros of the fraction are dropped before the decimal point is placed.
  int fraction = decimals;
  while (fraction > 0 && length > 1 && digits[static_cast<std::size_t>(length - 1)] == '0') {
    --length;
    --fraction;
  }
  if (magnitude == 0) {
    out += '0';
    return;
  }
  if (negative) out += '-';
  if (length <= fraction) {
    out += "0.";
    out.append(static_cast<std::size_t>(fraction - length), '0');
    out.append(digits.data(), static_cast<std::size_t>(length));
    return;
  }
  const auto whole = static_cast<std::size_t>(length - fraction);
  out.append(digits.data(), whole);
  if (fraction > 0) {
    out += '.';
    out.append(digits.data() + whole, static_cast<std::size_t>(fraction));
  }
}

void appendFixed(std::string& out, double value, int decimals) {
  const double counts = value * pow10(decimals);
  if (std::abs(counts) < 9e18) {
    appendCounts(out, std::llround(counts), decimals);
    return;
  }
  // Beyond 64-bit counts (a feed rate of 1e300 in a canonical file) llround has no answer: print
  // the double itself, trailing zeros trimmed as above.
  std::array<char, 400> text{};
  const auto result = std::to_chars(text.data(), text.data() + text.size(), value,
                                    std::chars_format::fixed, decimals);
  std::string_view printed(text.data(), static_cast<std::size_t>(result.ptr - text.data()));
  if (printed.find('.') != std::string_view::npos) {
    while (printed.back() == '0') printed.remove_suffix(1);
    if (printed.back() == '.') printed.remove_suffix(1);
  }
  out += printed;
}

bool isToolNumber(double value) noexcept {
  return value >= 0.0 && value <= kMaxToolNumber && value == std::floor(value);
}

}  // namespace volcomp::nc
