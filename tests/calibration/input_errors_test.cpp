// Bad measurement CSVs and bad templates are rejected with messages naming file, line/key, what.

#include <gtest/gtest.h>

#include <sstream>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;

// Returns the ConfigError message of parsing `text`, or "" when it parsed.
std::string csvError(const std::string& text) {
  std::istringstream input(text);
  try {
    parseMeasurementsCsv(input, "points.csv");
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), "points.csv");
    return e.what();
  }
  return {};
}

TEST(MeasurementCsv, ReadsRequiredAndOptionalColumnsInAnyOrder) {
  std::istringstream input(
      "# comment line\n"
      "ex,ey,ez,x,y,z,weight,tx,ty,tz\n"
      "0.001,-0.002,3e-4,10,20,-30,2,0,0,100\n"
      "\n"
      "+0.5,0,0,1,2,3,1,0,0,50\n");
  const MeasurementSet set = parseMeasurementsCsv(input, "points.csv");
  ASSERT_EQ(set.points.size(), 2u);
  EXPECT_TRUE(set.hasTool);
  EXPECT_FALSE(set.hasAngles);
  EXPECT_EQ(set.points[0].qMm, Eigen::Vector3d(10, 20, -30));
  EXPECT_EQ(set.points[0].errorMm, Eigen::Vector3d(0.001, -0.002, 3e-4));
  EXPECT_EQ(set.points[0].toolMm, Eigen::Vector3d(0, 0, 100));
  EXPECT_EQ(set.points[0].weight, 2.0);
  EXPECT_EQ(set.points[0].line, 3);
  EXPECT_EQ(set.points[1].line, 5);
  EXPECT_EQ(set.points[1].errorMm.x(), 0.5);
}

TEST(MeasurementCsv, RejectsBadInputNamingLineAndColumn) {
  EXPECT_NE(csvError("x,y,z,ex,ey\n1,2,3,4,5\n").find("missing column \"ez\""), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez,foo\n").find("unknown column \"foo\""), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez,x\n").find("appears twice"), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez,tx\n").find("tx,ty,tz"), std::string::npos);
  const std::string badNumber = csvError("x,y,z,ex,ey,ez\n1,2,3,0,0,0\n1,2,abc,0,0,0\n");
  EXPECT_NE(badNumber.find("points.csv: line 3, column z"), std::string::npos) << badNumber;
  EXPECT_NE(badNumber.find("\"abc\""), std::string::npos) << badNumber;
  EXPECT_NE(csvError("x,y,z,ex,ey,ez\n1,2,3,0,0\n").find("line 2"), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez\n1,2,3,0,0,nan\n").find("column ez"), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez,weight\n1,2,3,0,0,0,-1\n").find("weight > 0"),
            std::string::npos);
  EXPECT_NE(csvError("").find("empty file"), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez\n").find("no measurement rows"), std::string::npos);
  EXPECT_NE(csvError("x,y,z,ex,ey,ez,q2\n").find("q1..qN"), std::string::npos);
}

// An unknown column of 100 kB made a 100 kB message, escape sequences and invalid UTF-8
// went to the terminal as they were. Shown now escaped, quoted and shortened.
TEST(MeasurementCsv, AnUnknownColumnIsShownEscapedAndShort) {
  const std::string message =
      csvError("x,y,z,ex,ey,ez,\x1b[31m\xff" + std::string(100000, 'c') + "\n1,2,3,4,5,6,7\n");
  EXPECT_LT(message.size(), 400u) << message;
  EXPECT_NE(message.find("points.csv: line 1: unknown column \"\\x1b[31m\\xffccc"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("...\" (expected x,y,z,ex,ey,ez"), std::string::npos) << message;
  EXPECT_EQ(message.find('\x1b'), std::string::npos);
}

// A line of a million columns is refused as a line, not split into a million fields.
TEST(MeasurementCsv, AMillionColumnLineIsRefused) {
  std::string text = "x,y,z,ex,ey,ez\n";
  for (int i = 0; i < 1000000; ++i) text += "0,";
  text += "0\n";
  EXPECT_EQ(csvError(text), "points.csv: line 2: longer than 1 MiB: not a line of this format");
}

TEST(MeasurementCsv, ADirectoryIsNamedAsSuch) {
  try {
    readMeasurementsCsv("/");
    ADD_FAILURE() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_STREQ(e.what(), "/: is a directory, not a file");
  }
}

TEST(MeasurementCsv, MissingFileIsAConfigError) {
  EXPECT_THROW(readMeasurementsCsv("/nonexistent/points.csv"), config::ConfigError);
}

// Returns the ConfigError message of building a problem for `components`, or "".
std::string templateError(const json& components) {
  const json t{{"format", "volcomp-model/1"}, {"topology", "FXYZ"}, {"components", components}};
  std::istringstream input("x,y,z,ex,ey,ez\n0,0,0,0,0,0\n100,0,0,0,0,0\n");
  const MeasurementSet data = parseMeasurementsCsv(input, "points.csv");
  try {
    config::ParseOptions options;
    options.allowIdentify = true;
    makeIdentificationProblem(config::parseModel(t, "template.json", options), data);
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), "template.json");
    return e.what();
  }
  return {};
}

TEST(CalibrationTemplate, RejectsBadIdentifyBlocksNamingTheKey) {
  EXPECT_EQ(templateError({{"EXX", {{"identify", "constant"}}}}), "");
  const std::string word = templateError({{"EXX", {{"identify", "linear"}}}});
  EXPECT_NE(word.find("components.EXX.identify"), std::string::npos) << word;
  const std::string basis = templateError({{"EXX", {{"identify", {{"basis", "spline"}}}}}});
  EXPECT_NE(basis.find("components.EXX.identify.basis"), std::string::npos) << basis;
  const std::string degree =
      templateError({{"EBX", {{"identify", {{"basis", "polynomial"}, {"degree", -1}}}}}});
  EXPECT_NE(degree.find("components.EBX.identify.degree"), std::string::npos) << degree;
  const std::string positions =
      templateError({{"EXX", {{"identify", {{"basis", "table"}, {"positions", {0, 100, 50}}}}}}});
  EXPECT_NE(positions.find("components.EXX.identify.positions[2]"), std::string::npos) << positions;
  EXPECT_NE(positions.find("strictly increasing"), std::string::npos) << positions;
  const json tableBlock{{"basis", "table"}, {"positions", {0, 100}}, {"interpolation", "spline"}};
  const std::string interpolation = templateError({{"EXX", {{"identify", tableBlock}}}});
  EXPECT_NE(interpolation.find("identify.interpolation"), std::string::npos) << interpolation;
  const std::string location =
      templateError({{"EC0Y", {{"identify", {{"basis", "polynomial"}, {"degree", 1}}}}}});
  EXPECT_NE(location.find("location error is a constant"), std::string::npos) << location;
  const std::string extra =
      templateError({{"EXX", {{"identify", {{"basis", "constant"}, {"degree", 1}}}}}});
  EXPECT_NE(extra.find("components.EXX.identify.degree"), std::string::npos) << extra;
  const json cubicStart{{"polynomial", {1, 2, 3}}};
  const json linearBasis{{"basis", "polynomial"}, {"degree", 1}};
  const std::string start =
      templateError({{"EXX", {{"identify", linearBasis}, {"start", cubicStart}}}});
  EXPECT_NE(start.find("components.EXX.start"), std::string::npos) << start;
}

TEST(CalibrationTemplate, APolynomialOnAnAxisWithoutTravelIsRefusedBeforeTheFit) {
  // The model reader refuses a polynomial without the axis' travel, so calibrate must not write
  // one: the template is refused up front, naming the component and the travel it needs.
  const json straightness{{"basis", "polynomial"}, {"degree", 3}};
  const std::string message = templateError({{"EYX", {{"identify", straightness}}}});
  EXPECT_NE(message.find("template.json"), std::string::npos) << message;
  EXPECT_NE(message.find("components.EYX.identify"), std::string::npos) << message;
  EXPECT_NE(message.find("\"travel\": {\"X\": [min, max]}"), std::string::npos) << message;
  // A constant (degree 0) is bounded: no travel needed, as for the reader.
  const json constant{{"basis", "polynomial"}, {"degree", 0}};
  EXPECT_EQ(templateError({{"EYX", {{"identify", constant}}}}), "");
}

TEST(CalibrationTemplate, JointColumnsAreRejectedForAThreeAxisModel) {
  const json t{{"format", "volcomp-model/1"},
               {"topology", "FXYZ"},
               {"components", {{"EXX", {{"identify", "constant"}}}}}};
  std::istringstream input("x,y,z,ex,ey,ez,q1\n0,0,0,0,0,0,1\n");
  const MeasurementSet data = parseMeasurementsCsv(input, "points.csv");
  config::ParseOptions options;
  options.allowIdentify = true;
  try {
    makeIdentificationProblem(config::parseModel(t, "template.json", options), data);
    FAIL() << "expected a ConfigError";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), "points.csv");
    EXPECT_NE(std::string(e.what()).find("D-H"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace volcomp::calibration
