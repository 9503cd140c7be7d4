// volcomp::format against printf: each function must print exactly what the printf conversion it
// names prints, since the text it replaced was printf's and tests, files and people read it.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "volcomp/format/numbers.hpp"

namespace volcomp::format {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string printf1(const char* conversion, int precision, double value) {
  std::array<char, 512> buffer{};
  std::snprintf(buffer.data(), buffer.size(), conversion, precision, value);
  return buffer.data();
}

// Values where printf's rules show: exact ties (x.5, 0.125), negative zero, rounding up to a new
// digit (9.9995), the switch to exponent notation of %g (1e-5, 1e15), subnormals, huge values.
std::vector<double> edgeValues() {
  std::vector<double> values{0.0,
                             -0.0,
                             0.125,
                             0.375,
                             2.5,
                             -2.5,
                             0.5,
                             1.5,
                             -4e-4,
                             9.9995,
                             99999.5,
                             999999.5,
                             1e-5,
                             1e-4,
                             5e-5,
                             1.5e-4,
                             1e-7,
                             1e15,
                             1e16,
                             1e21,
                             123456789.0,
                             1e300,
                             -1e300,
                             kNan,
                             -kNan,
                             kInf,
                             -kInf,
                             0.1 + 0.2,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max()};
  // Every binary fraction k/2^n is an exact tie at some precision.
  for (int n = 1; n <= 8; ++n) {
    for (int k = -40; k <= 40; ++k) values.push_back(std::ldexp(k, -n));
  }
  return values;
}

std::vector<double> randomValues() {
  std::mt19937_64 random(20240611);
  std::uniform_real_distribution<double> exponent(-12.0, 12.0);
  std::vector<double> values;
  for (int i = 0; i < 20000; ++i) {
    const double magnitude = std::pow(10.0, exponent(random));
    values.push_back(i % 2 == 0 ? magnitude : -magnitude);
  }
  return values;
}

TEST(FormatNumbers, FixedIsPrintfF) {
  for (const std::vector<double>& values : {edgeValues(), randomValues()}) {
    for (double v : values) {
      for (int decimals = 0; decimals <= 17; ++decimals) {
        ASSERT_EQ(fixed(v, decimals), printf1("%.*f", decimals, v)) << v << " " << decimals;
        ASSERT_EQ(signedFixed(v, decimals), printf1("%+.*f", decimals, v)) << v << " " << decimals;
      }
    }
  }
}

TEST(FormatNumbers, GeneralIsPrintfG) {
  for (const std::vector<double>& values : {edgeValues(), randomValues()}) {
    for (double v : values) {
      for (int digits = 0; digits <= 17; ++digits) {
        ASSERT_EQ(general(v, digits), printf1("%.*g", digits, v)) << v << " " << digits;
      }
      ASSERT_EQ(general(v), printf1("%.*g", 6, v)) << v;
    }
  }
}

TEST(FormatNumbers, ExamplesAsDocumented) {
  EXPECT_EQ(fixed(1.25, 3), "1.250");
  EXPECT_EQ(fixed(2.5, 0), "2");  // a tie goes to even, as printf rounds it
  EXPECT_EQ(fixed(-0.0001, 3), "-0.000");
  EXPECT_EQ(fixed(kNan, 3), "nan");
  EXPECT_EQ(fixed(-kNan, 3), "-nan");
  EXPECT_EQ(fixed(-kInf, 3), "-inf");
  EXPECT_EQ(signedFixed(1.25, 4), "+1.2500");
  EXPECT_EQ(signedFixed(-0.001, 4), "-0.0010");
  EXPECT_EQ(signedFixed(0.0, 4), "+0.0000");
  EXPECT_EQ(general(0.5), "0.5");
  EXPECT_EQ(general(1e-5), "1e-05");
  EXPECT_EQ(general(1234567.0), "1.23457e+06");
  EXPECT_EQ(general(0.1 + 0.2, 17), "0.30000000000000004");
  EXPECT_EQ(general(0.0001, 10), "0.0001");
}

TEST(FormatNumbers, NegativePrecisionIsSixAsInPrintf) {
  EXPECT_EQ(fixed(1.5, -1), printf1("%.*f", -1, 1.5));
  EXPECT_EQ(signedFixed(1.5, -3), printf1("%+.*f", -3, 1.5));
  EXPECT_EQ(general(1.0 / 3.0, -2), printf1("%.*g", -2, 1.0 / 3.0));
}

TEST(FormatNumbers, NothingIsCutShort) {
  EXPECT_EQ(fixed(1e300, 7).size(), 301U + 8U);
  EXPECT_EQ(fixed(-std::numeric_limits<double>::max(), 17),
            printf1("%.*f", 17, -std::numeric_limits<double>::max()));
}

TEST(FormatNumbers, FixedUnsignedZeroDropsTheSignOfARoundedZeroOnly) {
  EXPECT_EQ(fixedUnsignedZero(-0.0001, 3), "0.000");
  EXPECT_EQ(fixedUnsignedZero(-0.0, 7), "0.0000000");
  EXPECT_EQ(fixedUnsignedZero(-0.4, 0), "0");
  EXPECT_EQ(fixedUnsignedZero(-0.0005, 3), "-0.001");
  EXPECT_EQ(fixedUnsignedZero(-0.6, 0), "-1");
  EXPECT_EQ(fixedUnsignedZero(-12.5, 1), "-12.5");
  EXPECT_EQ(fixedUnsignedZero(-kNan, 3), "-nan");
  EXPECT_EQ(fixedUnsignedZero(-kInf, 3), "-inf");
  for (double v : randomValues()) {
    const std::string printed = printf1("%.*f", 3, v);
    const bool roundedZero = printed.find_first_not_of("-0.") == std::string::npos;
    ASSERT_EQ(fixedUnsignedZero(v, 3), roundedZero ? "0.000" : printed) << v;
  }
}

TEST(FormatNumbers, FixedSignificantChoosesTheDecimals) {
  EXPECT_EQ(fixedSignificant(16.237, 4, 3), "16.24");
  EXPECT_EQ(fixedSignificant(0.0123456, 4, 3), "0.012");
  EXPECT_EQ(fixedSignificant(123456.7, 4, 3), "123457");
  EXPECT_EQ(fixedSignificant(1234.4, 4, 3), "1234");
  EXPECT_EQ(fixedSignificant(-3.25, 4, 3), "-3.250");
  EXPECT_EQ(fixedSignificant(0.0, 4, 3), "0.000");
  EXPECT_EQ(fixedSignificant(-0.0001, 4, 3), "-0.000");
  EXPECT_EQ(fixedSignificant(kNan, 4, 3), "nan");
  EXPECT_EQ(fixedSignificant(-kInf, 4, 3), "-inf");
  EXPECT_EQ(fixedSignificant(0.5, 2, 0), "0");
  // The decimals come from the value before rounding, as the helpers this replaced computed them.
  EXPECT_EQ(fixedSignificant(9.9996, 4, 3), "10.000");
  for (double v : randomValues()) {
    const int exponent = static_cast<int>(std::floor(std::log10(std::abs(v))));
    const int decimals = std::clamp(3 - exponent, 0, 3);
    ASSERT_EQ(fixedSignificant(v, 4, 3), printf1("%.*f", decimals, v)) << v;
  }
}

TEST(FormatNumbers, HexIdIsACanIdentifier) {
  EXPECT_EQ(hexId(0x123, false), "0x123");
  EXPECT_EQ(hexId(0x7, false), "0x007");
  EXPECT_EQ(hexId(0x7FF, false), "0x7FF");
  EXPECT_EQ(hexId(0x18FF0010, true), "0x18FF0010");
  EXPECT_EQ(hexId(0x10, true), "0x00000010");
  EXPECT_EQ(hexId(0xABCDEu, false), "0xABCDE");  // wider than 3 digits: all of them, as printf
}

TEST(FormatNumbers, HexBytesAreSpaceSeparated) {
  const std::uint8_t bytes[] = {0x01, 0xA0, 0xFF, 0x00};
  EXPECT_EQ(hexBytes(bytes), "01 A0 FF 00");
  EXPECT_EQ(hexBytes(std::span<const std::uint8_t>(bytes, 1)), "01");
  EXPECT_EQ(hexBytes({}), "");
}

}  // namespace
}  // namespace volcomp::format
