// Numbers on screen (config/display_units.hpp): µm and µrad or arcsec, 4 significant digits,
// at most 3 decimals, no trailing zeros, no "-0".

#include <gtest/gtest.h>

#include <limits>

#include "volcomp/config/display_units.hpp"

namespace volcomp::config {
namespace {

TEST(DisplayUnits, FourSignificantDigitsAtMostThreeDecimals) {
  EXPECT_EQ(significant(16.237), "16.24");
  EXPECT_EQ(significant(1234.4), "1234");
  EXPECT_EQ(significant(123456.7), "123457");
  EXPECT_EQ(significant(0.0123456), "0.012");
  EXPECT_EQ(significant(-3.25), "-3.25");
  EXPECT_EQ(significant(15.6), "15.6");
  EXPECT_EQ(significant(250.0), "250");
  EXPECT_EQ(significant(0.0), "0");
  EXPECT_EQ(significant(-0.0001), "0");
  EXPECT_EQ(significant(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(significant(std::numeric_limits<double>::quiet_NaN()), "nan");
}

TEST(DisplayUnits, LengthsInMicrometresAnglesInMicroradiansOrArcseconds) {
  EXPECT_EQ(micrometres(0.0156), "15.6 um");
  EXPECT_EQ(micrometres(-0.0049), "-4.9 um");
  EXPECT_EQ(angle(18.5e-6, AngleDisplay::Microradian), "18.5 urad");
  EXPECT_EQ(angle(4.84813681109536e-6, AngleDisplay::Arcsecond), "1 arcsec");
  EXPECT_EQ(angleDisplayFromName("arcsec"), AngleDisplay::Arcsecond);
  EXPECT_THROW(angleDisplayFromName("deg"), std::invalid_argument);
}

}  // namespace
}  // namespace volcomp::config
