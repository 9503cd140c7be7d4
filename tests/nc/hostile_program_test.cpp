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
std::string refusal(ProgramReader& reader, const std::string& program, long& line) {
  OffsetField field(std::make_shared<const model::MachineModel>(cubeSpec()),
                    model::EvalMode::Exact);
  Compensator c(field, {}, Vec3(10, 20, -30));
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

std::string ngcRefusal(const std::string& program, long& line) {
  NgcReader reader("hostile.ngc", {}, {}, Vec3(10, 20, -30), {});
  return refusal(reader, program, line);
}

std::string canonRefusal(const std::string& program, long& line) {
  CanonReader reader("hostile.canon", Vec3(10, 20, -30), {});
  return refusal(reader, program, line);
}

// Fuzz finding (canon): STRAIGHT_FEED to Y 10090000 mm planned 100 million check points (16 s
// and gigabytes for one line; 1e300 would never end).
TEST(HostilePrograms, AMoveTooLongToCheckIsRefusedAtItsLine) {
  long line = 0;
  const std::string canon =
      "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
      "    2 N..... STRAIGHT_FEED(10.0000, 20.0000, -30.0000, 0.0000, 0.0000, 0.0000)\n"
      "    3 N..... STRAIGHT_FEED(544.0000, 10090000, -4.0000, 0.0000, 0.0000, 0.0000)\n";
  const std::string message = canonRefusal(canon, line);
  EXPECT_EQ(line, 3);
  EXPECT_NE(message.find("hostile.canon:3"), std::string::npos) << message;
  EXPECT_NE(message.find("check points"), std::string::npos) << message;

  line = 0;
  EXPECT_NE(ngcRefusal("G21 G90\nG1 X1000000000 F100\n", line).find("check points"),
            std::string::npos);
  EXPECT_EQ(line, 2);
  // A long move within the bound is still compensated.
  EXPECT_EQ(ngcRefusal("G21 G90\nG1 X50000 F100\n", line), "");
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
