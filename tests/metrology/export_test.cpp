// Controller tables: what each plan carries, the files' exact text on small tables, and the error
// left when only the tables are applied.

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>

#include "volcomp/metrology/controller_files.hpp"
#include "volcomp/metrology/export_plan.hpp"
#include "volcomp/metrology/remaining_error.hpp"

namespace volcomp::metrology {
namespace {

using model::Axis;

model::TableSpec table(std::vector<double> positions, std::vector<double> values,
                       std::vector<double> negative = {}) {
  model::TableSpec t;
  t.positionsMm = std::move(positions);
  t.values = std::move(values);
  t.valuesNegative = std::move(negative);
  return t;
}

/// XYFZ with a bidirectional EXX whose nodes lie on the export grid (every 50 mm), EZZ, a
/// straightness EYX and squareness EC0Y.
model::MachineModelSpec machine() {
  model::MachineModelSpec spec;
  spec.topology = "XYFZ";
  spec.travelMm = {std::array<double, 2>{0, 200}, std::array<double, 2>{0, 100},
                   std::array<double, 2>{-100, 0}};
  spec.toolMm = Eigen::Vector3d(0, 0, 100);
  spec.motion[0] = table({0, 50, 100, 150, 200}, {0, 0.002, 0.003, 0.005, 0.006},
                         {0.004, 0.006, 0.0065, 0.009, 0.0095});
  spec.motion[static_cast<std::size_t>(model::motionIndex(Axis::Z, model::MotionKind::EZ))] =
      table({-100, -50, 0}, {-0.003, -0.001, 0});
  spec.motion[static_cast<std::size_t>(model::motionIndex(Axis::X, model::MotionKind::EY))] =
      table({0, 100, 200}, {0, 0.002, 0});
  spec.locationRad[static_cast<std::size_t>(model::locationIndex(Axis::Y, 2))] = 20e-6;
  return spec;
}

TEST(ExportPlan, LinuxCncCarriesPositioningOnly) {
  const model::MachineModelSpec spec = machine();
  const ExportPlan plan = planLinuxCnc(spec, {50, 50, 50});
  ASSERT_EQ(plan.tables.size(), 3u);  // X forward, X reverse, Z both
  EXPECT_EQ(plan.tables[0].direction, 1);
  EXPECT_EQ(plan.tables[1].direction, -1);
  EXPECT_EQ(plan.tables[2].input, Axis::Z);
  EXPECT_EQ(plan.tables[2].direction, 0);
  // X is workpiece-side: e = -EXX; Z is tool-side: e = +EZZ.
  EXPECT_NEAR(plan.tables[0].errorMm[1], -0.002, 1e-15);
  EXPECT_NEAR(plan.tables[1].errorMm[1], -0.006, 1e-15);
  EXPECT_NEAR(plan.tables[2].errorMm[0], -0.003, 1e-15);
  ASSERT_EQ(plan.carried.size(), 2u);
  ASSERT_EQ(plan.notCarried.size(), 2u);
  EXPECT_EQ(plan.notCarried[0].rfind("EYX: straightness", 0), 0u) << plan.notCarried[0];
  EXPECT_EQ(plan.notCarried[1].rfind("EC0Y: squareness", 0), 0u) << plan.notCarried[1];
}

TEST(ExportPlan, SiemensSplitsReversalAndCarriesCrossAxisTables) {
  const model::MachineModelSpec spec = machine();
  const ExportPlan plan = planSiemens(spec, {50, 50, 50});
  // LEC X (mean), CEC X+ and X- (curve minus mean), LEC Z, CEC X->Y (EYX), CEC Y->X (EC0Y).
  ASSERT_EQ(plan.tables.size(), 6u);
  const AxisTable& mean = plan.tables[0];
  const AxisTable& up = plan.tables[1];
  const AxisTable& down = plan.tables[2];
  for (std::size_t i = 0; i < mean.errorMm.size(); ++i) {
    const double exxUp = std::get<model::TableSpec>(spec.motion[0]).values[i];
    const double exxDown = std::get<model::TableSpec>(spec.motion[0]).valuesNegative[i];
    EXPECT_NEAR(mean.errorMm[i] + up.errorMm[i], -exxUp, 1e-15);
    EXPECT_NEAR(mean.errorMm[i] + down.errorMm[i], -exxDown, 1e-15);
  }
  EXPECT_EQ(up.direction, 1);
  EXPECT_EQ(down.direction, -1);
  EXPECT_EQ(plan.tables[4].input, Axis::X);
  EXPECT_EQ(plan.tables[4].output, Axis::Y);
  EXPECT_NEAR(plan.tables[4].errorMm[2], -0.002, 1e-15);  // workpiece-side X: e = -EYX
  EXPECT_EQ(plan.tables[5].input, Axis::Y);
  EXPECT_EQ(plan.tables[5].output, Axis::X);
  EXPECT_TRUE(plan.notCarried.empty()) << plan.notCarried.front();
}

TEST(RemainingError, TablesCancelWhatTheyCarry) {
  // Positioning only, nodes on the grid: the tables hold the model's values exactly, but a
  // controller looks them up at the commanded position while the error arises at the corrected
  // one, so slope x correction remains: 4e-5 x 1e-2 mm = 4e-7 mm at most here. The live solve
  // leaves nothing.
  model::MachineModelSpec spec = machine();
  spec.motion[static_cast<std::size_t>(model::motionIndex(Axis::X, model::MotionKind::EY))] = 0.0;
  spec.locationRad.fill(0.0);
  const ExportPlan plan = planLinuxCnc(spec, {50, 50, 50});
  const RemainingError r = remainingError(spec, plan.tables, 5);
  EXPECT_EQ(r.directionCombinations, 8u);
  EXPECT_EQ(r.evaluations, 5u * 5u * 5u * 8u);
  EXPECT_NEAR(r.uncompensated.maxMm, std::hypot(0.0095, 0.003), 1e-12);
  EXPECT_LT(r.tablesOnly.maxMm, 1e-6);
  EXPECT_GT(r.tablesOnly.maxMm, 1e-8);
  EXPECT_LT(r.live.maxMm, 1e-9);
  EXPECT_EQ(r.liveNotConverged, 0u);
}

TEST(RemainingError, WhatATableCannotCarryRemains) {
  const model::MachineModelSpec spec = machine();
  const RemainingError linuxcnc = remainingError(spec, planLinuxCnc(spec, {50, 50, 50}).tables, 5);
  const RemainingError siemens = remainingError(spec, planSiemens(spec, {50, 50, 50}).tables, 5);
  // EYX (2 um bow) and EC0Y (20 urad over 100 mm = 2 um) stay with LinuxCNC.
  EXPECT_GT(linuxcnc.tablesOnly.maxMm, 0.002);
  // Siemens carries all of them (EYX is linear between its nodes in the model as in the table);
  // what remains is the second-order lookup effect above.
  EXPECT_LT(siemens.tablesOnly.maxMm, 1e-6);
  EXPECT_GT(siemens.uncompensated.maxMm, 0.009);
}

TEST(ControllerFiles, LinuxCncTypesZeroAndOne) {
  AxisTable forward;
  forward.grid = {0, 10, 3};
  forward.errorMm = {0.001, -0.002, 0.0};
  AxisTable reverse = forward;
  reverse.errorMm = {0.004, 0.001, 0.003};
  std::ostringstream type0, type1;
  writeLinuxCncCompFile(type0, forward, reverse, 0);
  writeLinuxCncCompFile(type1, forward, reverse, 1);
  // Type 0: where the joint is (nominal + e); type 1: the trims LinuxCNC adds (-e).
  EXPECT_EQ(type0.str(),
            "0.000000 0.0010000 0.0040000\n"
            "10.000000 9.9980000 10.0010000\n"
            "20.000000 20.0000000 20.0030000\n");
  EXPECT_EQ(type1.str(),
            "0.000000 -0.0010000 -0.0040000\n"
            "10.000000 0.0020000 -0.0010000\n"
            "20.000000 0.0000000 -0.0030000\n");
}

TEST(ControllerFiles, SiemensPartPrograms) {
  AxisTable lec;
  lec.input = lec.output = Axis::Y;
  lec.grid = {-10, 2.5, 2};
  lec.errorMm = {0.0012346, -0.002};
  lec.components = {"EYY"};
  std::ostringstream out;
  writeSiemensLec(out, {lec}, {"AX1", "AX2", "AX3"}, 0, {"comment"});
  EXPECT_EQ(out.str(),
            "%_N_AX_EEC_INI\n"
            "; comment\n"
            "CHANDATA(1)\n"
            "; Y (AX2): EYY error e = actual - nominal, mm (a positive value moves the axis in -)\n"
            "$AA_ENC_COMP[0,0,AX2]=0.001235\n"
            "$AA_ENC_COMP[0,1,AX2]=-0.002000\n"
            "$AA_ENC_COMP_STEP[0,AX2]=2.5\n"
            "$AA_ENC_COMP_MIN[0,AX2]=-10.0\n"
            "$AA_ENC_COMP_MAX[0,AX2]=-7.5\n"
            "$AA_ENC_COMP_IS_MODULO[0,AX2]=0\n"
            "M17\n");
  AxisTable cec = lec;
  cec.input = Axis::X;
  cec.output = Axis::Z;
  cec.direction = -1;
  cec.components = {"EZX"};
  std::ostringstream cecOut;
  writeSiemensCec(cecOut, {cec}, {"X1", "Y1", "Z1"}, {});
  EXPECT_EQ(cecOut.str(),
            "%_N_NC_CEC_INI\n"
            "CHANDATA(1)\n"
            "; table 0: EZX - error of Z over X, moving -, mm\n"
            "$AN_CEC[0,0]=0.001235\n"
            "$AN_CEC[0,1]=-0.002000\n"
            "$AN_CEC_INPUT_AXIS[0]=(X1)\n"
            "$AN_CEC_OUTPUT_AXIS[0]=(Z1)\n"
            "$AN_CEC_STEP[0]=2.5\n"
            "$AN_CEC_MIN[0]=-10.0\n"
            "$AN_CEC_MAX[0]=-7.5\n"
            "$AN_CEC_DIRECTION[0]=-1\n"
            "$AN_CEC_MULT_BY_TABLE[0]=0\n"
            "$AN_CEC_IS_MODULO[0]=0\n"
            "M17\n");
}

TEST(ControllerFiles, ComponentCsvHoldsTheComponentsOwnValues) {
  const model::MachineModelSpec spec = machine();
  std::ostringstream out;
  writeComponentCsv(out, spec, "EXX", {0, 100, 3});
  std::istringstream lines(out.str());
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "position_mm,value_um,value_negative_um");
  const double expected[3][3] = {{0, 0, 4}, {100, 3, 6.5}, {200, 6, 9.5}};
  for (const auto& row : expected) {
    ASSERT_TRUE(std::getline(lines, line));
    double position = 0, up = 0, down = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &position, &up, &down), 3) << line;
    EXPECT_DOUBLE_EQ(position, row[0]);
    EXPECT_NEAR(up, row[1], 1e-12);
    EXPECT_NEAR(down, row[2], 1e-12);
  }
  std::ostringstream square;
  writeComponentCsv(square, spec, "EC0Y", {0, 100, 2});
  EXPECT_EQ(square.str(), "position_mm,value_urad\n0.0,20.0\n100.0,20.0\n");
  EXPECT_THROW(planComponent(spec, "EQQ", {0, 0, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace volcomp::metrology
