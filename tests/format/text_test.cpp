// Column padding against printf's %-*s and %*s.

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

#include "volcomp/format/text.hpp"

namespace volcomp::format {
namespace {

std::string printf1(const char* conversion, int width, const char* text) {
  std::array<char, 64> buffer{};
  std::snprintf(buffer.data(), buffer.size(), conversion, width, text);
  return buffer.data();
}

TEST(FormatText, PaddingIsPrintfs) {
  for (const char* text : {"", "X", "total", "12.34", "a longer text than the column"}) {
    for (int width = 0; width <= 16; ++width) {
      EXPECT_EQ(padRight(text, static_cast<std::size_t>(width)), printf1("%-*s", width, text));
      EXPECT_EQ(padLeft(text, static_cast<std::size_t>(width)), printf1("%*s", width, text));
    }
  }
}

TEST(FormatText, Examples) {
  EXPECT_EQ(padRight("X", 6), "X     ");
  EXPECT_EQ(padLeft("1.5", 6), "   1.5");
  EXPECT_EQ(padLeft("1234567", 6), "1234567");
}

}  // namespace
}  // namespace volcomp::format
