// The simulator's NC programs (volcomp-sim nc-run and the simulated machine's program path) with
// positions a wrong offset or unit makes: each is refused at its line instead of sampling for
// ever (1e15 mm at a 0.01 mm step) or converting an unbounded count to an integer.
#include <gtest/gtest.h>

#include <string>

#include "temp_files.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/sim/nc_program.hpp"
#include "volcomp/sim/nc_run.hpp"

namespace volcomp::sim {
namespace {

std::string trueModel() {
  return std::string(VOLCOMP_SOURCE_DIR) + "/config/examples/vmc-xyfz-21-true.json";
}

/// readNcProgram's refusal of `program` ("" when accepted); `line` is set to its line.
std::string refusal(const testing::TempDir& dir, const std::string& program, long& line) {
  NcProgramSpec spec;
  spec.file = dir.write("p.ngc", program);
  try {
    readNcProgram(spec);
  } catch (const nc::NcError& e) {
    line = e.line();
    return e.what();
  }
  return "";
}

TEST(SimulatorPrograms, PositionsBeyondAKilometreAreRefusedAtTheirLine) {
  const testing::TempDir dir;
  long line = 0;
  std::string message = refusal(dir, "G21 G90\nG0 X0 Y0 Z0\nG1 X1000000000000000 F100\n", line);
  EXPECT_NE(message.find("X at 1e+15 mm is beyond +-1e+06 mm"), std::string::npos) << message;
  EXPECT_EQ(line, 3);
  message = refusal(
      dir, "G21 G90 G17\nG0 X10 Y20 Z-30\nG2 X10 Y20 I100000000000000000000 J0 F100\n", line);
  EXPECT_NE(message.find("an arc of radius 1e+20 mm reaches beyond"), std::string::npos) << message;
  EXPECT_EQ(line, 3);
  EXPECT_EQ(refusal(dir, "G21 G90\nG0 X0 Y0 Z0\nG1 X999999 F100\n", line), "");
}

TEST(SimulatorPrograms, AMoveNeedingTooManyPiecesIsRefusedAtItsLine) {
  const testing::TempDir dir;
  // 10000 turns of a 1 km circle within 1e-5 mm: 7e9 chords.
  NcRunOptions o;
  o.program.file = dir.write("arc.ngc",
                             "G21 G90 G17\nG0 X10 Y20 Z-30\nG1 X11 F100\n"
                             "G2 X11 Y20 I1000000 J0 P10000 F100\n");
  o.reference = o.program;
  o.trueModel = trueModel();
  try {
    runNcProgram(o);
    FAIL() << "accepted";
  } catch (const nc::NcError& e) {
    EXPECT_EQ(e.line(), 4);
    EXPECT_NE(std::string(e.what()).find("chords within 1e-05 mm, more than the 1e+07"),
              std::string::npos)
        << e.what();
  }
  // A kilometre at the smallest --step: 1e7 samples are the most one move may have.
  o.program.file = dir.write("line.ngc", "G21 G90\nG0 X0 Y0 Z0\nG1 X2000 F100\n");
  o.reference = o.program;
  o.stepMm = 1e-4;
  try {
    runNcProgram(o);
    FAIL() << "accepted";
  } catch (const nc::NcError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("samples at --step"), std::string::npos) << e.what();
  }
}

TEST(SimulatorPrograms, RecordedPositionsBeyondAKilometreAreRefusedAtTheirRow) {
  const testing::TempDir dir;
  NcProgramSpec reference;
  reference.file = dir.write("ok.ngc", "G21 G90\nG0 X0 Y0 Z0\nG1 X10 F100\n");
  const std::string record = dir.write("rec.csv", "x,y,z,ox,oy,oz\n1,0,0,0,0,0\n1e300,0,0,0,0,0\n");
  try {
    measureRecordedRun(record, reference, trueModel());
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("rec.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("beyond +-1e6 mm"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace volcomp::sim
