// Number text and line tokenizing (nc/numbers.hpp, nc/block.hpp).
#include <gtest/gtest.h>

#include "volcomp/nc/block.hpp"
#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc {
namespace {

double scan(std::string_view text, std::size_t& pos) {
  double v = 0.0;
  EXPECT_TRUE(scanNumber(text, pos, v)) << text;
  return v;
}

TEST(Numbers, ScansRs274Reals) {
  std::size_t pos = 0;
  EXPECT_EQ(scan("12.5", pos), 12.5);
  EXPECT_EQ(pos, 4u);
  pos = 0;
  EXPECT_EQ(scan("-.5Y", pos), -0.5);
  EXPECT_EQ(pos, 3u);
  pos = 0;
  EXPECT_EQ(scan("+3.", pos), 3.0);
  pos = 0;
  // LinuxCNC ignores blanks inside numbers: "1 0 . 5" is 10.5.
  EXPECT_EQ(scan(" 1 0 . 5 X", pos), 10.5);
  EXPECT_EQ(pos, 8u);
}

TEST(Numbers, RejectsWhatIsNotANumber) {
  double v = 7.0;
  for (std::string_view bad : {"", "-", ".", "X1", "#1", "1.2.3"}) {
    std::size_t pos = 0;
    const bool ok = scanNumber(bad, pos, v);
    if (bad == "1.2.3") {
      // A second point ends the number: "1.2" is read, ".3" remains.
      EXPECT_TRUE(ok);
      EXPECT_EQ(v, 1.2);
      EXPECT_EQ(pos, 3u);
      continue;
    }
    EXPECT_FALSE(ok) << bad;
    EXPECT_EQ(pos, 0u);
  }
  std::size_t pos = 0;
  EXPECT_FALSE(scanNumber("1e3", pos, v) && pos == 3) << "no exponents in RS274/NGC";
}

TEST(Numbers, CountsAreExactDecimals) {
  const auto text = [](std::int64_t counts, int decimals) {
    std::string s;
    appendCounts(s, counts, decimals);
    return s;
  };
  EXPECT_EQ(text(1234500, 5), "12.345");
  EXPECT_EQ(text(1200000, 5), "12");
  EXPECT_EQ(text(-5, 5), "-0.00005");
  EXPECT_EQ(text(0, 3), "0");
  EXPECT_EQ(text(100, 5), "0.001");
  EXPECT_EQ(text(-123456789, 6), "-123.456789");
  EXPECT_EQ(text(42, 0), "42");
  std::string s;
  appendFixed(s, -0.0000001, 5);
  EXPECT_EQ(s, "0") << "no negative zero";
  // Beyond 64-bit counts (a feed rate of 1e300 in a canonical file) the double is printed.
  s.clear();
  appendFixed(s, 1e25, 6);
  EXPECT_EQ(s, "10000000000000000905969664");
  s.clear();
  appendFixed(s, -12345678901234.5, 6);
  EXPECT_EQ(s, "-12345678901234.5");
}

TEST(Tokenize, WordsWithColumnsAndComments) {
  Block b;
  LineError e;
  ASSERT_TRUE(tokenize("N10 g1 x1.5 Y -2 (cut) F100 ; rest", b, e));
  ASSERT_EQ(b.wordCount, 5);
  EXPECT_EQ(b.words[0].letter, 'N');
  EXPECT_EQ(b.words[1].letter, 'G');
  EXPECT_EQ(b.words[1].value, 1.0);
  EXPECT_EQ(b.words[2].letter, 'X');
  EXPECT_EQ(b.words[2].begin, 7u);
  EXPECT_EQ(b.words[2].end, 11u);
  EXPECT_EQ(b.words[3].value, -2.0);
  EXPECT_EQ(b.words[4].value, 100.0);
  EXPECT_TRUE(b.comment);
  ASSERT_TRUE(tokenize("  %  ", b, e));
  EXPECT_TRUE(b.percent);
  ASSERT_TRUE(tokenize("(only a comment)", b, e));
  EXPECT_EQ(b.wordCount, 0);
}

struct Rejection {
  const char* line;
  int column;
  const char* contains;
};

TEST(Tokenize, RejectsOutsideTheSubsetWithColumn) {
  const Rejection cases[] = {
      {"G1 X#1", 5, "parameters"},
      {"#1 = 5", 1, "parameters"},
      {"G1 X[1+2]", 5, "expressions"},
      {"o100 sub", 1, "O-words"},
      {"/G1 X1", 1, "block delete"},
      {"G1 @1 ^30", 4, "polar"},
      {"G1 X1 (open", 7, "closing"},
      {"G1 (a (b) c)", 7, "nested"},
      {"G1 X", 4, "expected a number after X"},
      {"G1 X1 $", 7, "unexpected character"},
  };
  for (const Rejection& c : cases) {
    Block b;
    LineError e;
    EXPECT_FALSE(tokenize(c.line, b, e)) << c.line;
    EXPECT_EQ(e.column, c.column) << c.line;
    EXPECT_NE(e.message.find(c.contains), std::string::npos) << c.line << ": " << e.message;
  }
}

}  // namespace
}  // namespace volcomp::nc
