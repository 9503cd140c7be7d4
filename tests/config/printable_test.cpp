// printable(), quoted() and ConfigError's message: what a message shows of the input is printable
// valid UTF-8 of bounded length, whatever the input held.

#include <gtest/gtest.h>

#include <string>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"

namespace volcomp::config {
namespace {

TEST(Printable, KeepsPrintableAsciiAndUtf8) {
  const std::string text = "deviation [\xC2\xB5m] x\xCC\x84\xE2\x86\x91 \\ \"q\" 1,5";
  EXPECT_EQ(printable(text), text);
  EXPECT_TRUE(isPrintable(text));
}

TEST(Printable, EscapesControlCharactersAndTerminalEscapes) {
  EXPECT_EQ(printable("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(printable("\x1b[31mred\x1b[0m"), "\\x1b[31mred\\x1b[0m");
  EXPECT_EQ(printable(std::string("nul\0x", 5)), "nul\\x00x");
  EXPECT_EQ(printable("del\x7f"), "del\\x7f");
  // C1 controls (CSI = U+009B), bidirectional overrides, line separators: as \uHHHH.
  EXPECT_EQ(printable("\xC2\x9B"
                      "2J"),
            "\\u009b2J");
  EXPECT_EQ(printable("abc\xE2\x80\xAE"
                      "fed"),
            "abc\\u202efed");
  EXPECT_EQ(printable("\xE2\x80\xA8"), "\\u2028");
  EXPECT_FALSE(isPrintable("\x1b"));
  EXPECT_FALSE(isPrintable("\xE2\x80\xAE"));
}

TEST(Printable, EscapesEachByteOfInvalidUtf8) {
  EXPECT_EQ(printable("\xFF"), "\\xff");
  EXPECT_EQ(printable("\xC0\xAF"), "\\xc0\\xaf");                    // overlong '/'
  EXPECT_EQ(printable("\xED\xA0\x80"), "\\xed\\xa0\\x80");           // a surrogate
  EXPECT_EQ(printable("\xF4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
  EXPECT_EQ(printable("\xE2\x86"), "\\xe2\\x86");                    // cut short
  EXPECT_EQ(printable("ok\xE2\x86!"), "ok\\xe2\\x86!");
  EXPECT_FALSE(isPrintable("\xC0\xAF"));
}

TEST(Printable, CutsAtACharacterBoundaryWithinTheLimit) {
  const std::string big(100000, 'x');
  const std::string shown = printable(big, 60);
  EXPECT_EQ(shown.size(), 60u);
  EXPECT_EQ(shown.substr(57), "...");
  // A multi-byte character is never split, an escape never cut in half.
  std::string arrows;
  for (int i = 0; i < 40; ++i) arrows += "\xE2\x86\x91";
  const std::string cut = printable(arrows, 20);
  EXPECT_LE(cut.size(), 20u);
  EXPECT_TRUE(isPrintable(cut));
  EXPECT_EQ(cut, "\xE2\x86\x91\xE2\x86\x91\xE2\x86\x91\xE2\x86\x91\xE2\x86\x91...");
  EXPECT_EQ(printable(std::string(30, '\x1b'), 12), "\\x1b\\x1b...");
  // Text that fits exactly is not cut.
  EXPECT_EQ(printable("abcdef", 6), "abcdef");
}

TEST(Printable, QuotedEscapesQuotesAndIsBounded) {
  EXPECT_EQ(config::quoted("say \"hi\""), "\"say \\\"hi\\\"\"");
  EXPECT_EQ(config::quoted(std::string(1000, 'a')).size(), kQuotedBytes + 2);
}

TEST(Printable, PassingTwiceChangesNothing) {
  const std::string raw = "\x1b[2J\xFF\n\xE2\x80\xAE ok \\x41";
  EXPECT_EQ(printable(printable(raw)), printable(raw));
}

TEST(ConfigErrorMessage, WhatIsPrintableAndBoundedAccessorsKeepTheParts) {
  const std::string file = "dir/\x1b]0;title\x07.json";
  const std::string key = "components.\xFF\xFE";
  const std::string message = "unknown column " + std::string(100000, 'c');
  const ConfigError e(file, key, message);
  const std::string what = e.what();
  EXPECT_TRUE(isPrintable(what)) << what;
  EXPECT_LT(what.size(), 4096u);
  EXPECT_EQ(what.rfind("dir/\\x1b]0;title\\x07.json: components.\\xff\\xfe: unknown column ccc", 0),
            0u)
      << what;
  EXPECT_EQ(e.file(), file);
  EXPECT_EQ(e.keyPath(), key);
  EXPECT_EQ(e.message(), message);
  // An ordinary message is unchanged.
  EXPECT_STREQ(ConfigError("m.json", "components.EXX.values[2]", "expected a finite number").what(),
               "m.json: components.EXX.values[2]: expected a finite number");
}

}  // namespace
}  // namespace volcomp::config
