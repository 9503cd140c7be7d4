#pragma once
/// Number text of NC programs, with std::from_chars / std::to_chars (locale-free, no allocation
/// beyond the output string's growth).
///
/// Printed coordinates are integer counts of 10^-decimals program units (mm or inch): the text is
/// exactly that decimal, so G91 increments written as differences of counts add up exactly.

#include <cstdint>
#include <string>
#include <string_view>

namespace volcomp::nc {

/// Scans an RS274/NGC real number starting at `pos`: an optional sign, digits with at most one
/// decimal point, at least one digit; spaces and tabs between its characters are skipped, as
/// LinuxCNC does in programs ("X 1 0.5" is X10.5; `blanksInside` false for files where blanks
/// separate numbers). No exponent. On success `pos` is after the number and `value` is set; on
/// failure `pos` is unchanged and false is returned.
bool scanNumber(std::string_view line, std::size_t& pos, double& value,
                bool blanksInside = true) noexcept;

/// Appends counts * 10^-decimals as decimal text without trailing zeros: (1234500, 5) -> "12.345",
/// (1200000, 5) -> "12", (-5, 5) -> "-0.00005", (0, 3) -> "0". decimals in 0..9.
void appendCounts(std::string& out, std::int64_t counts, int decimals);

/// Appends `value` rounded to `decimals` decimals, trailing zeros trimmed, "-0" written as "0"
/// (beyond 9e18 counts, the double's exact decimal expansion rounded to `decimals`).
void appendFixed(std::string& out, double value, int decimals);

/// 10^decimals as a double (decimals in 0..9).
double pow10(int decimals) noexcept;

/// The largest tool number accepted (T, M61 Q, G43 H, tool tables): the largest int.
inline constexpr double kMaxToolNumber = 2147483647.0;

/// Whether `value` is a tool number: a whole number in 0..kMaxToolNumber (so that converting it to
/// int is exact; NaN and infinities are not).
bool isToolNumber(double value) noexcept;

}  // namespace volcomp::nc
