#pragma once
/// Numbers as text, one function per way volcomp prints them. Each prints exactly what the named
/// printf conversion prints (in the "C" locale): the same digits, the same rounding (the exact
/// binary value, ties to even), "-0.000" for a negative value that rounds to zero unless the
/// function says otherwise, "nan", "-nan", "inf" and "-inf" for values that are not finite. Unlike
/// a fixed-size printf buffer, nothing is ever cut short.

#include <cstdint>
#include <span>
#include <string>

namespace volcomp::format {

/// printf "%.*f": `decimals` digits after the point ("1.250" for fixed(1.25, 3); no point for
/// 0 decimals). A negative `decimals` means 6, as in printf.
std::string fixed(double value, int decimals);

/// printf "%+.*f": fixed() with the sign always written ("+1.2500", "-0.0010", "+0.0000").
std::string signedFixed(double value, int decimals);

/// fixed(), except that a value whose printed digits are all zero has no minus sign: "0.000" for
/// -0.0001 with 3 decimals, where printf prints "-0.000". Other values, "-nan" and "-inf" included,
/// are printed as fixed() prints them.
std::string fixedUnsignedZero(double value, int decimals);

/// printf "%.*f" with the decimals that show `significant` significant digits of `value`, clamped
/// to [0, maxDecimals]: significant - 1 - floor(log10|value|). Zero, NaN and infinities get
/// maxDecimals. fixedSignificant(16.237, 4, 3) = "16.24", fixedSignificant(0.0123456, 4, 3) =
/// "0.012", fixedSignificant(123456.7, 4, 3) = "123457", fixedSignificant(0.0, 4, 3) = "0.000".
std::string fixedSignificant(double value, int significant, int maxDecimals);

/// printf "%.*g": `significant` significant digits (0 means 1, a negative value 6), in fixed or
/// exponent notation as printf chooses, without trailing zeros: general(0.5) = "0.5",
/// general(1e-5) = "1e-05", general(1234567.0) = "1.23457e+06", general(0.1 + 0.2, 17) =
/// "0.30000000000000004".
std::string general(double value, int significant = 6);

/// A CAN identifier as candump and DBC tools write it, printf "0x%08X" for an extended (29-bit)
/// identifier and "0x%03X" for a standard (11-bit) one: "0x123", "0x18FF0010".
std::string hexId(std::uint32_t id, bool extended);

/// Bytes as printf "%02X" each, separated by one space: "01 A0 FF"; "" for no bytes.
std::string hexBytes(std::span<const std::uint8_t> bytes);

}  // namespace volcomp::format
