// The RS274/NGC interpreter of the subset: positions in machine coordinates through work offsets,
// G92, tool offsets, units and distance modes; arcs as LinuxCNC computes them; rejections with
// the column of the word (nc/ngc_interpreter.hpp). LinuxCNC itself checks the same programs in
// rs274_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "volcomp/nc/ngc_interpreter.hpp"

namespace volcomp::nc {
namespace {

constexpr double kPi = std::numbers::pi;

class Interpreter : public ::testing::Test {
 protected:
  Interpreter() {
    offsets_.systemsMm[0] = Vec3(100, 50, -20);
    offsets_.systemsMm[1] = Vec3(200, 10, 0);
    tools_[1] = Vec3(0, 0, 25.5);
  }

  NgcLine run(NgcInterpreter& interp, std::string_view line) {
    Block block;
    LineError error;
    NgcLine out;
    EXPECT_TRUE(tokenize(line, block, error)) << line << ": " << error.message;
    EXPECT_TRUE(interp.execute(block, out, error)) << line << ": " << error.message;
    return out;
  }

  LineError reject(NgcInterpreter& interp, std::string_view line) {
    Block block;
    LineError error;
    NgcLine out;
    if (tokenize(line, block, error) && interp.execute(block, out, error)) {
      ADD_FAILURE() << "accepted: " << line;
    }
    return error;
  }

  WorkOffsets offsets_;
  ToolTable tools_;
};

void expectNear(const Vec3& a, const Vec3& b, double tol = 1e-12) {
  EXPECT_LT((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

TEST_F(Interpreter, WorkOffsetsUnitsDistanceModes) {
  NgcInterpreter in(offsets_, tools_, std::nullopt, {});
  NgcLine l = run(in, "G21 G90 G0 X1 Y2 Z3");
  EXPECT_TRUE(l.motion);
  EXPECT_FALSE(l.startKnown);
  EXPECT_TRUE(l.endKnown);
  expectNear(l.move.endMm, Vec3(101, 52, -17));
  l = run(in, "G91 G1 X1 F100");
  EXPECT_TRUE(l.startKnown);
  expectNear(l.move.endMm, Vec3(102, 52, -17));
  EXPECT_TRUE(l.after.incremental);
  l = run(in, "G90 G20 G1 X1");
  expectNear(l.move.endMm, Vec3(125.4, 52, -17));
  EXPECT_EQ(l.after.frame.unitMm, 25.4);
  EXPECT_EQ(l.after.decimals, Decimals{}.inch);
  l = run(in, "G21 G55 X0 Y0");
  expectNear(l.move.endMm, Vec3(200, 10, -17));
  l = run(in, "G43 H1 Z0");
  expectNear(l.move.endMm, Vec3(200, 10, 25.5));
  l = run(in, "G49 G53 G0 Z-5");
  expectNear(l.move.endMm, Vec3(200, 10, -5));
  EXPECT_TRUE(l.after.machineCoordinates);
  l = run(in, "Z-5");
  // G53 is not modal: Z-5 in G55 (Z offset 0, no tool offset) is machine -5 again.
  expectNear(l.move.endMm, Vec3(200, 10, -5));
}

TEST_F(Interpreter, StartPositionAndUnknownAxes) {
  NgcInterpreter unknown(offsets_, tools_, std::nullopt, {});
  NgcLine l = run(unknown, "G0 Z5");
  EXPECT_FALSE(l.endKnown);
  l = run(unknown, "X1 Y1");
  EXPECT_TRUE(l.endKnown);
  NgcInterpreter known(offsets_, tools_, Vec3(1, 2, 3), {});
  l = run(known, "G91 G0 X1");
  EXPECT_TRUE(l.startKnown);
  expectNear(l.move.endMm, Vec3(2, 2, 3));
}

TEST_F(Interpreter, ArcsInEachPlaneAsLinuxCncComputesThem) {
  WorkOffsets none;
  NgcInterpreter in(none, tools_, Vec3(0, 0, 0), {});
  NgcLine l = run(in, "G17 G2 X10 Y0 I5 J0 F100");
  ASSERT_EQ(l.move.kind, MoveKind::Arc);
  EXPECT_DOUBLE_EQ(l.move.arc.centerFirst, 5.0);
  EXPECT_NEAR(l.move.arc.sweep, -kPi, 1e-12);
  expectNear(l.move.at(0.5), Vec3(5, 5, 0), 1e-12);
  // R form: the centre found as LinuxCNC's arc_data_r finds it; negative R takes the long way.
  l = run(in, "G3 X0 Y0 R5");
  EXPECT_NEAR(l.move.arc.sweep, kPi, 1e-12);
  expectNear(l.move.at(0.5), Vec3(5, 5, 0), 1e-9);
  l = run(in, "G2 X10 Y0 R-5.1");
  EXPECT_LT(l.move.arc.sweep, -kPi);
  // Full circle with two turns and a helix along Z.
  l = run(in, "G3 I-5 J0 Z-2 P2");
  EXPECT_NEAR(l.move.arc.sweep, 4 * kPi, 1e-12);
  expectNear(l.move.at(0.25), Vec3(0, 0, -0.5), 1e-9);
  // G18: the plane is (Z, X); G2 is clockwise in that order.
  run(in, "G0 X0 Y0 Z0");
  l = run(in, "G18 G2 X10 Z0 I5 K0");
  EXPECT_EQ(l.move.arc.first, 2);
  EXPECT_EQ(l.move.arc.second, 0);
  EXPECT_NEAR(l.move.arc.sweep, -kPi, 1e-12);
  expectNear(l.move.at(0.5), Vec3(5, 0, -5), 1e-9);
  // G19: the plane is (Y, Z).
  run(in, "G0 X0 Y0 Z0");
  l = run(in, "G19 G3 Y10 Z0 J5 K0");
  EXPECT_EQ(l.move.arc.first, 1);
  expectNear(l.move.at(0.5), Vec3(0, 5, -5), 1e-9);
  // G90.1: absolute centre.
  run(in, "G17 G0 X0 Y0 Z0");
  l = run(in, "G90.1 G2 X10 Y0 I5 J0");
  EXPECT_DOUBLE_EQ(l.move.arc.centerFirst, 5.0);
  l = run(in, "G2 X20 Y0 I15 J0");
  EXPECT_DOUBLE_EQ(l.move.arc.centerFirst, 15.0);
}

struct Rejected {
  const char* line;
  int column;
  const char* contains;
};

TEST_F(Interpreter, RejectsOutsideTheSubset) {
  const Rejected cases[] = {
      {"G41 D1", 1, "cutter radius compensation"},
      {"G0 X1 G81 Z-1 R1", 7, "canned cycle"},
      {"G92 X0", 1, "G92"},
      {"G10 L2 P1 X0", 1, "offsets set by the program"},
      {"G38.2 Z-10 F10", 1, "probing"},
      {"G93 G1 X1 F1", 1, "inverse time"},
      {"M70", 1, "modal state"},
      {"G1 A10 F1", 4, "axis A"},
      {"G0 X1 G1 Y1", 7, "same modal group"},
      {"X1", 1, "without a motion"},
      {"G1 X1", 4, "zero feed rate"},
      {"F10 G17 G2 X1 K1", 15, "K word with an arc in the XY"},
      {"F10 G2 X10 Y0 I5 J1", 15, "radius to the end"},
      {"G43 H9", 1, "tool 9 is not in the tool table"},
      {"G91 G53 G0 X1", 1, "G53 in incremental"},
      {"G1 X1 X2 F1", 7, "given twice"},
      {"M98 P100", 1, "M98 is not in the supported subset"},
  };
  for (const Rejected& c : cases) {
    NgcInterpreter in(offsets_, tools_, Vec3(0, 0, 0), {});
    const LineError e = reject(in, c.line);
    EXPECT_EQ(e.column, c.column) << c.line << ": " << e.message;
    EXPECT_NE(e.message.find(c.contains), std::string::npos) << c.line << ": " << e.message;
  }
}

TEST_F(Interpreter, RotatedCoordinateSystemIsRejected) {
  WorkOffsets rotated = offsets_;
  rotated.rotationDeg[1] = 30.0;
  NgcInterpreter in(rotated, tools_, Vec3(0, 0, 0), {});
  const LineError e = reject(in, "G55 G0 X1");
  EXPECT_NE(e.message.find("rotat"), std::string::npos) << e.message;
}

TEST_F(Interpreter, ProgramEndAndStopCodes) {
  NgcInterpreter in(offsets_, tools_, Vec3(0, 0, 0), {});
  NgcLine l = run(in, "G1 X5 F100 M0");
  EXPECT_EQ(l.stopWords, 1ull << 3);
  l = run(in, "M30");
  EXPECT_TRUE(l.programEnd);
  EXPECT_TRUE(in.ended());
}

}  // namespace
}  // namespace volcomp::nc
