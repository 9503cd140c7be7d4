#include "volcomp/model/topology.hpp"

#include <set>

#include <gtest/gtest.h>

namespace volcomp::model {
namespace {

TEST(Topology, XYFZ) {
  const Topology t = Topology::parse("XYFZ");
  EXPECT_EQ(t.text(), "XYFZ");
  EXPECT_EQ(t.workpieceSideFromFrame(), (std::vector<Axis>{Axis::Y, Axis::X}));
  EXPECT_EQ(t.toolSideFromFrame(), (std::vector<Axis>{Axis::Z}));
  EXPECT_TRUE(t.isWorkpieceSide(Axis::X));
  EXPECT_TRUE(t.isWorkpieceSide(Axis::Y));
  EXPECT_FALSE(t.isWorkpieceSide(Axis::Z));
}

TEST(Topology, FXYZAndXYZF) {
  const Topology tool = Topology::parse("FXYZ");
  EXPECT_TRUE(tool.workpieceSideFromFrame().empty());
  EXPECT_EQ(tool.toolSideFromFrame(), (std::vector<Axis>{Axis::X, Axis::Y, Axis::Z}));
  const Topology work = Topology::parse("XYZF");
  EXPECT_EQ(work.workpieceSideFromFrame(), (std::vector<Axis>{Axis::Z, Axis::Y, Axis::X}));
  EXPECT_TRUE(work.toolSideFromFrame().empty());
}

TEST(Topology, All24PermutationsParse) {
  const std::vector<std::string> all = allTopologies();
  EXPECT_EQ(all.size(), 24u);
  EXPECT_EQ(std::set<std::string>(all.begin(), all.end()).size(), 24u);
  for (const std::string& text : all) {
    const Topology t = Topology::parse(text);
    EXPECT_EQ(t.workpieceSideFromFrame().size() + t.toolSideFromFrame().size(), 3u) << text;
  }
}

TEST(Topology, RejectsBadStrings) {
  for (const char* bad :
       {"", "FXY", "FXYZZ", "fxyz", "FXXZ", "FXYA", "XYZ ", "XYZ", "FFXY", "XFYZF"}) {
    EXPECT_THROW(Topology::parse(bad), ModelError) << bad;
  }
}

TEST(Types, Names) {
  EXPECT_EQ(motionName(motionIndex(Axis::X, MotionKind::EB)), "EBX");
  EXPECT_EQ(motionName(motionIndex(Axis::Y, MotionKind::EY)), "EYY");
  EXPECT_EQ(motionName(motionIndex(Axis::Z, MotionKind::EC)), "ECZ");
  EXPECT_EQ(locationName(locationIndex(Axis::Y, 2)), "EC0Y");
  EXPECT_EQ(locationName(locationIndex(Axis::Z, 0)), "EA0Z");
  EXPECT_THROW(motionName(18), ModelError);
  EXPECT_THROW(locationName(-1), ModelError);
}

TEST(Types, AxisFromName) {
  EXPECT_EQ(axisFromName("X"), Axis::X);
  EXPECT_EQ(axisFromName("Y"), Axis::Y);
  EXPECT_EQ(axisFromName("Z"), Axis::Z);
  for (const char* bad : {"", "x", "W", "XY", " X", "X "}) EXPECT_FALSE(axisFromName(bad)) << bad;
}

}  // namespace
}  // namespace volcomp::model
