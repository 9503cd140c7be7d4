// Programs a fuzzer found or a careless export makes: a move kilometres long, an arc of 1e20
// turns. Each is refused at its line with a message, quickly and without a huge allocation,
// by both readers (fuzz/ngc_fuzzer.cpp, fuzz/canon_fuzzer.cpp find such programs).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "volcomp/nc/canon_reader.hpp"
#include "volcomp/nc/compensator.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/ngc_reader.hpp"

namespace volcomp::nc {
namespace {

model::MachineModelSpec cubeSpec() {
  model::MachineModelSpec s;
  s.topology = "FXYZ";
  s.travelMm = {std::array<double, 2>{0, 850}, std::array<double, 2>{0, 500},
                std::array<double, 2>{-500, 0}};
  s.motion[motionIndex(model::Axis::X, model::MotionKind::EX)] = 0.01;
  return s;
}

/// Compensates `program` with `reader`; returns the NcError's message ("" when accepted) and
/// sets `line` to its line.
std::string refusal(ProgramReader& reader, const std::string& program, long& line,
                    const CompensateOptions& options = {}) {
  OffsetField field(std::make_shared<const model::MachineModel>(cubeSpec()),
                    model::EvalMode::Exact);
  Compensator c(field, options, Vec3(10, 20, -30));
  StringSource source(program);
  StringSink sink;
  try {
    c.run(reader, source, sink);
  } catch (const NcError& e) {
    line = e.line();
    return e.what();
  }
  return "";
}

std::string ngcRefusal(const std::string& program, long& line,
                       const CompensateOptions& options = {}) {
  NgcReader reader("hostile.ngc", {}, {}, Vec3(10, 20, -30), {});
  return refusal(reader, program, line, options);
}

std::string canonRefusal(const std::string& program, long& line) {
  CanonReader reader("hostile.canon", Vec3(10, 20, -30), {});
  return refusal(reader, program, line);
}

// Fuzz finding (canon): STRAIGHT_FEED to Y 10090000 mm planned 100 million check points (16 s
// and gigabytes for one line; 1e300 would never end). Such a line is now refused before, as a
// position beyond a kilometre (next test); the bound on check points still refuses a move within
// that range that would need too many (here with a check step of 0.1 mm).
TEST(HostilePrograms, AMoveTooLongToCheckIsRefusedAtItsLine) {
  long line = 0;
  const std::string canon =
      "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
      "    2 N..... STRAIGHT_FEED(10.0000, 20.0000, -30.0000, 0.0000, 0.0000, 0.0000)\n"
      "    3 N..... STRAIGHT_FEED(544.0000, 10090000, -4.0000, 0.0000, 0.0000, 0.0000)\n";
  const std::string message = canonRefusal(canon, line);
  EXPECT_EQ(line, 3);
  EXPECT_NE(message.find("hostile.canon:3"), std::string::npos) << message;
  EXPECT_NE(message.find("beyond +-1e+06 mm"), std::string::npos) << message;

  line = 0;
  CompensateOptions fine;
  fine.checkStepMm = 0.1;
  EXPECT_NE(ngcRefusal("G21 G90\nG1 X900000 F100\n", line, fine).find("check points"),
            std::string::npos);
  EXPECT_EQ(line, 2);
  // A long move within the bound is still compensated.
  EXPECT_EQ(ngcRefusal("G21 G90\nG1 X50000 F100\n", line), "");
}

// Fuzz finding (canon): a work offset of 1e308 mm put a rapid at Y 1e308; its printed counts
// overflowed and the refinement cast an infinite deviation to int. A position beyond 1 km, in
// machine coordinates or in the program's frame, is refused at its line by both readers.
TEST(HostilePrograms, APositionBeyondAKilometreIsRefusedAtItsLine) {
  long line = 0;
  const std::string canon =
      "    1 N..... SET_G5X_OFFSET(1, 0.0000, 1e308, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "    2 N..... STRAIGHT_TRAVERSE(0.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)\n";
  std::string message = canonRefusal(canon, line);
  EXPECT_NE(message.find("beyond +-1e+06 mm"), std::string::npos) << message;
  EXPECT_NE(message.find("Y at 1e+308 mm"), std::string::npos) << message;
  EXPECT_EQ(line, 2);
  // In the program's frame only: machine Y 20, written as Y -1e9 under a 1e9 offset.
  const std::string canonFrame =
      "    1 N..... SET_G5X_OFFSET(1, 0.0000, 1000000020, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "    2 N..... STRAIGHT_FEED(10.0000, -1000000000, -30.0000, 0.0000, 0.0000, 0.0000)\n";
  message = canonRefusal(canonFrame, line);
  EXPECT_NE(message.find("in the program's frame"), std::string::npos) << message;
  EXPECT_EQ(line, 2);
  const std::string ngc = "G21 G90\nG0 X10 Y20 Z-30\nG0 X2000000\n";
  message = ngcRefusal(ngc, line);
  EXPECT_NE(message.find("beyond +-1e+06 mm"), std::string::npos) << message;
  EXPECT_EQ(line, 3);
  // An ordinary program is not.
  EXPECT_EQ(ngcRefusal("G21 G90\nG0 X10 Y20 Z-30\nG1 X100 F100\n", line), "");
}

// Fuzz finding (ngc): "G92.3<TAB>2" is one word (RS274 allows blanks inside a number), which the
// refusal quoted with its tab; a message is shown on a terminal, so control characters are
// escaped in every NcError.
TEST(HostilePrograms, AQuotedWordWithATabIsShownEscaped) {
  long line = 0;
  const std::string message = ngcRefusal("G92.3\t2\n", line);
  EXPECT_EQ(line, 1);
  EXPECT_NE(message.find("not a G code: G92.3\\t2"), std::string::npos) << message;
  EXPECT_EQ(message.find('\t'), std::string::npos) << message;
  const NcError escaped("a\x1b[2Jb.ngc", 3, 0, "bad \x01");
  EXPECT_STREQ(escaped.what(), "a\\x1b[2Jb.ngc:3: bad \\x01");
}

// Fuzz finding (ngc): "T44444444444444" was converted to int, which is undefined beyond the
// largest int. Tool numbers are bounded wherever they appear (T, M61 Q, G43 H, tool tables).
TEST(HostilePrograms, ToolNumbersBeyondTheLargestIntAreRefused) {
  const std::string expected = "tool number must be a whole number in 0..2147483647";
  for (const std::string word : {"T44444444444444", "T-1", "T1.5", "M61 Q2147483648",
                                 "M61 Q99999999999999999999", "G43 H1000000000000"}) {
    long line = 0;
    const std::string message = ngcRefusal("G21 G90\n" + word + "\nG1 X10 F100\n", line);
    EXPECT_NE(message.find(expected), std::string::npos) << word << ": " << message;
    EXPECT_EQ(line, 2) << word;
  }
  long line = 0;
  EXPECT_EQ(ngcRefusal("G21 G90\nT2147483647 M6\nG1 X10 F100\n", line), "");
  const std::string canon =
      "    1 N..... SELECT_TOOL(1e12)\n"
      "    2 N..... STRAIGHT_FEED(10.0000, 20.0000, -30.0000, 0.0000, 0.0000, 0.0000)\n";
  EXPECT_NE(canonRefusal(canon, line).find("SELECT_TOOL: " + expected), std::string::npos);
  EXPECT_EQ(line, 1);
}

TEST(HostilePrograms, ArcTurnsAreBounded) {
  long line = 0;
  EXPECT_NE(ngcRefusal("G21 G90 G17\nG2 X10 Y20 I5 J0 P100000000000000000000 F100\n", line)
                .find("P (turns"),
            std::string::npos);
  EXPECT_EQ(line, 2);
  const std::string canon =
      "    1 N..... STRAIGHT_FEED(10.0000, 20.0000, -30.0000, 0.0000, 0.0000, 0.0000)\n"
      "    2 N..... ARC_FEED(10.0000, 20.0000, 15.0000, 20.0000, -1e300, -30.0000, 0.0000, "
      "0.0000, 0.0000)\n";
  EXPECT_NE(canonRefusal(canon, line).find("rotation"), std::string::npos);
  EXPECT_EQ(line, 2);
  // Many turns, but a sane number, still go through.
  EXPECT_EQ(ngcRefusal("G21 G90 G17\nG2 X10 Y20 I5 J0 P3 F100\n", line), "");
}

}  // namespace
}  // namespace volcomp::nc
