// Work offsets and tool tables: LinuxCNC .var and .tbl files and the JSON format (nc/setup.hpp).
#include <gtest/gtest.h>

#include "volcomp/config/config_error.hpp"
#include "volcomp/nc/move.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/setup.hpp"

namespace volcomp::nc {
namespace {

TEST(VarFile, CoordinateSystemsActiveSystemAndG92) {
  const std::string text =
      "5210\t1.000000\n5211\t0.500000\n5212\t0\n5213\t-1\n5220\t2.000000\n"
      "5221\t100.000000\n5222\t50.000000\n5223\t-20.000000\n5241\t200\n5242\t10\n5243\t0\n"
      "5381 7\n5383 -3\n\n";
  WorkOffsets o;
  parseVarText(text, "t.var", LengthUnit::Mm, o);
  EXPECT_EQ(o.active, 1);
  EXPECT_EQ(o.systemsMm[0], Vec3(100, 50, -20));
  EXPECT_EQ(o.systemsMm[1], Vec3(200, 10, 0));
  EXPECT_EQ(o.systemsMm[8], Vec3(7, 0, -3));
  EXPECT_EQ(o.g92Mm, Vec3(0.5, 0, -1));
  WorkOffsets inch;
  parseVarText(text, "t.var", LengthUnit::Inch, inch);
  EXPECT_DOUBLE_EQ(inch.systemsMm[0].x(), 2540.0);
  EXPECT_DOUBLE_EQ(inch.g92Mm.x(), 12.7);
}

TEST(VarFile, G92OnlyWhenEnabled) {
  WorkOffsets o;
  parseVarText("5210 0\n5211 4\n", "t.var", LengthUnit::Mm, o);
  EXPECT_EQ(o.g92Mm, Vec3::Zero());
}

TEST(VarFile, RejectsMalformedLinesWithPosition) {
  WorkOffsets o;
  try {
    parseVarText("5221 1\n5222 abc\n", "p.var", LengthUnit::Mm, o);
    FAIL();
  } catch (const NcError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.column(), 6);
    EXPECT_STREQ(e.what(), "p.var:2:6: expected a number after parameter 5222");
  }
  EXPECT_THROW(parseVarText("5220 12\n", "p.var", LengthUnit::Mm, o), NcError);
}

TEST(ToolTable, OffsetsOfEachTool) {
  ToolTable t;
  parseToolTableText("T1 P1 Z25.5 D6 ;first\n\nT2 P2 X0.5 Z-10.25 D3\n;comment only\n", "t.tbl",
                     LengthUnit::Mm, t);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.at(1), Vec3(0, 0, 25.5));
  EXPECT_EQ(t.at(2), Vec3(0.5, 0, -10.25));
  ToolTable inch;
  parseToolTableText("T3 Z1\n", "t.tbl", LengthUnit::Inch, inch);
  EXPECT_DOUBLE_EQ(inch.at(3).z(), 25.4);
  try {
    parseToolTableText("T1 Z1\nP2 Z3\n", "x.tbl", LengthUnit::Mm, t);
    FAIL();
  } catch (const NcError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("without a T"), std::string::npos);
  }
  try {
    parseToolTableText("T1 Z1\nT99999999999 Z3\n", "x.tbl", LengthUnit::Mm, t);
    FAIL();
  } catch (const NcError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("0..2147483647"), std::string::npos) << e.what();
  }
}

TEST(WorkOffsetsJson, SystemsToolsAndUnits) {
  WorkOffsets o;
  ToolTable t;
  parseWorkOffsetsJson(R"({"format": "volcomp-work-offsets/1", "units": "inch", "active": "g55",
                           "coordinate_systems": {"G55": [1, 2, 3], "G59.3": [0, 0, 1]},
                           "g92": [0, 0, 0.5], "tools": {"1": 4, "7": [0.1, 0, 2]}})",
                       "w.json", o, t);
  EXPECT_EQ(o.active, 1);
  EXPECT_DOUBLE_EQ(o.systemsMm[1].z(), 76.2);
  EXPECT_DOUBLE_EQ(o.systemsMm[8].z(), 25.4);
  EXPECT_DOUBLE_EQ(o.g92Mm.z(), 12.7);
  EXPECT_DOUBLE_EQ(t.at(1).z(), 101.6);
  EXPECT_DOUBLE_EQ(t.at(7).x(), 2.54);
}

TEST(WorkOffsetsJson, KeyPathsInErrors) {
  WorkOffsets o;
  ToolTable t;
  const auto message = [&](const std::string& text) {
    try {
      parseWorkOffsetsJson(text, "w.json", o, t);
    } catch (const config::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(R"({"coordinate_systems": {"G60": [1, 2, 3]}})").find("coordinate_systems.G60"),
            std::string::npos);
  EXPECT_NE(message(R"({"coordinate_systems": {"G54": [1, 2]}})").find("coordinate_systems.G54"),
            std::string::npos);
  EXPECT_NE(message(R"({"unit": "mm"})").find("unknown key"), std::string::npos);
  EXPECT_NE(message(R"({"tools": {"x": 1}})").find("tools.x"), std::string::npos);
  EXPECT_NE(message(R"({"active": "G53"})").find("active"), std::string::npos);
}

TEST(CoordinateSystems, NamesAndIndices) {
  EXPECT_STREQ(coordinateSystemName(0), "G54");
  EXPECT_STREQ(coordinateSystemName(8), "G59.3");
  EXPECT_EQ(coordinateSystemIndex("g59.1"), 6);
  EXPECT_EQ(coordinateSystemIndex("G60"), -1);
}

}  // namespace
}  // namespace volcomp::nc
