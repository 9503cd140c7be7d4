// One test per class of rejection: each checks that the message names the file, the key path
// and what was expected (docs/model-file.md, "The whole file").

#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "temp_files.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

// Writes `text` to a model file, loads it and checks the ConfigError it must raise.
void expectRejected(const std::string& text, const std::string& keyPath,
                    const std::string& expectation, const ParseOptions& options = {}) {
  testing::TempDir dir;
  const std::string path = dir.write("model.json", text);
  try {
    loadModelFile(path, options);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), path) << what;
    EXPECT_EQ(e.keyPath(), keyPath) << what;
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    if (!keyPath.empty()) {
      EXPECT_NE(what.find(": " + keyPath + ": "), std::string::npos) << what;
    }
    EXPECT_NE(what.find(expectation), std::string::npos) << what << "\nlacks: " << expectation;
  }
}

// A valid FXYZ document with the given "components" body.
std::string withComponents(const std::string& components) {
  return R"({"format": "volcomp-model/1", "topology": "FXYZ", "components": {)" + components + "}}";
}

std::string withGrid(const std::string& grid) {
  return R"({"format": "volcomp-model/1", "topology": "FXYZ", "grids": [)" + grid + "]}";
}

std::string withLinks(const std::string& links) {
  return R"({"format": "volcomp-model/1", "chain": {"links": [)" + links + "]}}";
}

TEST(ModelFileRejects, MissingFile) {
  testing::TempDir dir;
  const std::string path = (dir.path() / "none.json").string();
  try {
    loadModelFile(path);
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find("cannot open file"), std::string::npos) << e.what();
  }
}

// A polynomial whose value overflows the double range inside the travel (1e306 um/mm^2 beyond
// X = 424 mm): the model would evaluate to infinity. Refused, naming the component and where.
TEST(ModelFileRejects, ModelThatEvaluatesToInfinity) {
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "travel": {"X": [0, 1000]},
    "error_units": {"length": "um", "angle": "urad"},
    "components": {"EXX": {"polynomial": [0, 0, 1e306]}}})",
                 "components.EXX", "the model's error is not finite at X ");
  // Two grids each within the double range whose sum is not.
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ",
    "error_units": {"length": "mm", "angle": "rad"}, "grids": [
      {"component": "EX", "over": ["X", "Y"], "axes": {"X": [0, 1], "Y": [0, 1]},
       "values": [[1e308, 1e308], [1e308, 1e308]]},
      {"component": "EX", "over": ["X", "Y"], "axes": {"X": [0, 1], "Y": [0, 1]},
       "values": [[1e308, 1e308], [1e308, 1e308]]}]})",
                 "grids", "not finite");
}

TEST(ModelFileRejects, MalformedJsonWithLineAndColumn) {
  expectRejected("{\n  \"format\": \"volcomp-model/1\",\n  \"topology\": FXYZ\n}", "",
                 "invalid JSON: parse error at line 3, column");
}

TEST(ModelFileRejects, NanLiteral) {
  expectRejected(withComponents(R"("EXX": NaN)"), "", "invalid JSON");
}

TEST(ModelFileRejects, NumberOverflow) {
  expectRejected(withComponents(R"("EXX": 1e400)"), "",
                 "at line 1, column 73: number 1e400 is out of the range of a double");
}

TEST(ModelFileRejects, NonFiniteNumberInAProgramBuiltDocument) {
  nlohmann::json doc = nlohmann::json::parse(withComponents(R"("EXX": {"positions": [0, 1],
      "values": [0, 1]})"));
  doc["components"]["EXX"]["values"][1] = std::numeric_limits<double>::infinity();
  try {
    parseModel(doc, "built.json");
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(),
                 "built.json: components.EXX.values[1]: expected a finite number, got "
                 "infinity");
  }
}

TEST(ModelFileRejects, DuplicateKey) {
  expectRejected(withComponents(R"("EXX": 1, "EXX": 2)"), "components.EXX", "duplicate key");
}

TEST(ModelFileRejects, NotAnObject) {
  expectRejected("[1, 2]", "", "expected a JSON object");
}

TEST(ModelFileRejects, WrongOrMissingFormat) {
  expectRejected(R"({"format": "volcomp-model/2", "topology": "FXYZ"})", "format",
                 "expected \"volcomp-model/1\", got \"volcomp-model/2\"");
  expectRejected(R"({"topology": "FXYZ"})", "format", "missing required key");
}

TEST(ModelFileRejects, UnknownTopLevelKey) {
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "tools": [0, 0, 1]})",
                 "tools", "unknown key; expected one of: format, name");
}

TEST(ModelFileRejects, UnknownComponentName) {
  expectRejected(withComponents(R"("EXW": 1)"), "components.EXW",
                 "unknown component; expected an ISO 230-1 name");
  expectRejected(withComponents(R"("EC0W": 1)"), "components.EC0W", "unknown component");
}

TEST(ModelFileRejects, WrongTypes) {
  expectRejected(withComponents(R"("EXX": "5")"), "components.EXX", "expected a number, a table");
  expectRejected(withComponents(R"("EXX": {"positions": [0, 1], "values": [0, "1"]})"),
                 "components.EXX.values[1]", "expected a number, got \"1\"");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "tool": "100"})", "tool",
                 "expected [x, y, z] in mm, got \"100\"");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "name": 5})", "name",
                 "expected a string, got 5");
  expectRejected(withComponents(R"("EC0Y": {"positions": [0, 1], "values": [0, 1]})"),
                 "components.EC0Y", "expected a number (a location error is a constant angle)");
}

TEST(ModelFileRejects, UnknownKeyInATable) {
  expectRejected(withComponents(R"("EXX": {"positions": [0, 1], "values": [0, 1], "unit": "um"})"),
                 "components.EXX.unit", "unknown key; expected one of: positions, values");
}

TEST(ModelFileRejects, NonIncreasingPositions) {
  expectRejected(withComponents(R"("EXX": {"positions": [0, 100, 100, 300],
                 "values": [0, 1, 2, 3]})"),
                 "components.EXX.positions[2]",
                 "expected a position greater than the previous one (100.0)");
}

TEST(ModelFileRejects, TooFewPositions) {
  expectRejected(withComponents(R"("EXX": {"positions": [0], "values": [0]})"),
                 "components.EXX.positions", "expected an array of at least 2 elements");
}

TEST(ModelFileRejects, MismatchedLengths) {
  expectRejected(withComponents(R"("EXX": {"positions": [0, 1, 2], "values": [0, 1]})"),
                 "components.EXX.values",
                 "expected an array of 3 numbers (one per position), got an array of 2");
  expectRejected(withComponents(R"("EXX": {"positions": [0, 1, 2], "values": [0, 1, 2],
                 "values_negative": [1, 2, 3, 4]})"),
                 "components.EXX.values_negative", "expected an array of 3 numbers");
}

TEST(ModelFileRejects, EvenNodeCountForQuadratic) {
  expectRejected(withComponents(R"("EYY": {"positions": [0, 1, 2, 3], "values": [0, 1, 2, 3],
                 "interpolation": "quadratic"})"),
                 "components.EYY.positions",
                 "expected an odd number of positions (>= 3) for quadratic interpolation");
}

TEST(ModelFileRejects, UnknownInterpolation) {
  expectRejected(withComponents(R"("EXX": {"positions": [0, 1], "values": [0, 1],
                 "interpolation": "spline"})"),
                 "components.EXX.interpolation",
                 "expected one of \"linear\", \"quadratic\", \"cubic\", got \"spline\"");
}

TEST(ModelFileRejects, EmptyPolynomial) {
  expectRejected(withComponents(R"("EBX": {"polynomial": []})"), "components.EBX.polynomial",
                 "expected an array of at least 1 elements");
  expectRejected(withComponents(R"("EBX": {"polynomial": [1], "positions": [0, 1]})"),
                 "components.EBX.positions", "unknown key; expected one of: polynomial");
}

TEST(ModelFileRejects, BadTopology) {
  for (const char* topology : {"XYZ", "XYFZF", "xyFz", "XXFZ", "FXYZ "}) {
    expectRejected(std::string(R"({"format": "volcomp-model/1", "topology": ")") + topology + "\"}",
                   "topology", "expected a topology string such as \"XYFZ\"");
  }
  expectRejected(R"({"format": "volcomp-model/1"})", "topology", "missing required key");
}

TEST(ModelFileRejects, BadUnits) {
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ",
                 "error_units": {"length": "inch"}})",
                 "error_units.length", "expected one of \"mm\", \"um\", \"nm\", got \"inch\"");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ",
                 "error_units": {"angle": "grad"}})",
                 "error_units.angle", "\"arcsec\", \"deg\", got \"grad\"");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ",
                 "error_units": {"lengths": "um"}})",
                 "error_units.lengths", "unknown key; expected one of: length, angle");
}

TEST(ModelFileRejects, BadTravel) {
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ",
                 "travel": {"X": [100, 0]}})",
                 "travel.X", "expected [min, max] with min < max, got an array of 2");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "travel": {"W": [0, 1]}})",
                 "travel.W", "unknown key; expected one of: X, Y, Z");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "travel": {"X": [0]}})",
                 "travel.X", "expected [min, max] in mm");
}

TEST(ModelFileRejects, GridWithWrongShape) {
  const std::string axes = R"("axes": {"X": [0, 100, 200], "Y": [0, 50]})";
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "Y"], )" + axes +
                          R"(, "values": [[0, 1], [2, 3]]})"),
                 "grids[0].values",
                 "expected an array of 3 arrays (one per node of axis 1 of \"over\"), got an "
                 "array of 2");
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "Y"], )" + axes +
                          R"(, "values": [[0, 1], [2, 3, 4], [5, 6]]})"),
                 "grids[0].values[1]",
                 "expected an array of 2 numbers (one per node of axis 2 of \"over\")");
}

TEST(ModelFileRejects, GridAxes) {
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "X"],
                 "axes": {"X": [0, 1]}, "values": [[0, 0], [0, 0]]})"),
                 "grids[0].over[1]", "expected an axis not already listed in \"over\"");
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X"],
                 "axes": {"X": [0, 1]}, "values": [0, 0]})"),
                 "grids[0].over", "expected an array of 2 to 3 elements");
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "Y"],
                 "axes": {"X": [0, 1]}, "values": [[0, 0], [0, 0]]})"),
                 "grids[0].axes.Y", "missing required key");
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "Y"],
                 "axes": {"X": [0, 1], "Y": [0, 1], "Z": [0, 1]}, "values": [[0, 0], [0, 0]]})"),
                 "grids[0].axes.Z", "unknown key; expected one of: X, Y");
  expectRejected(withGrid(R"({"component": "EA", "over": ["X", "Y"],
                 "axes": {"X": [0, 1], "Y": [0, 1]}, "values": [[0, 0], [0, 0]]})"),
                 "grids[0].component", "expected one of \"EX\", \"EY\", \"EZ\", got \"EA\"");
  expectRejected(withGrid(R"({"component": "EZ", "over": ["X", "Y"],
                 "axes": {"X": [0, 1], "Y": [1, 0]}, "values": [[0, 0], [0, 0]]})"),
                 "grids[0].axes.Y[1]", "positions must increase strictly");
}

TEST(ModelFileRejects, ChainLinks) {
  expectRejected(withLinks(R"({"joint": "spherical", "theta": 0, "d": 0, "a": 0, "alpha": 0})"),
                 "chain.links[0].joint", "expected one of \"prismatic\", \"revolute\", \"fixed\"");
  expectRejected(withLinks(R"({"joint": "revolute", "d": 0, "a": 0, "alpha": 0})"),
                 "chain.links[0].theta", "missing required key");
  expectRejected(withLinks(R"({"joint": "revolute", "theta": 0, "d": 0, "a": 0, "alpha": 0,
                 "dbeta": 1})"),
                 "chain.links[0].dbeta", "unknown key; expected one of: joint, theta");
  expectRejected(withLinks(R"({"joint": "revolute", "rotation_deg": [0, 0, 0]})"),
                 "chain.links[0].joint", "expected \"fixed\" for a transform link");
  expectRejected(withLinks(R"({"joint": "fixed", "translation": [0, 0]})"),
                 "chain.links[0].translation", "expected [x, y, z] in mm");
  expectRejected(R"({"format": "volcomp-model/1", "chain": {"links": []}})", "chain.links",
                 "expected an array of at least 1 elements");
  expectRejected(R"({"format": "volcomp-model/1", "chain": {"convention": "craig",
                 "links": []}})",
                 "chain.convention", "expected one of \"dh\", \"mdh\"");
  expectRejected(R"({"format": "volcomp-model/1", "topology": "FXYZ", "chain": {"links": []}})",
                 "topology", "unknown key; expected one of: format, name, description, chain");
}

TEST(ModelFileRejects, IdentifyOutsideCalibrationTemplates) {
  expectRejected(withComponents(R"("EXX": {"identify": {"kind": "table"}})"),
                 "components.EXX.identify",
                 "unknown key (\"identify\" is allowed in calibration templates only)");
  expectRejected(withLinks(R"({"joint": "revolute", "theta": 0, "d": 0, "a": 0, "alpha": 0,
                 "dalpha": {"identify": true}})"),
                 "chain.links[0].dalpha.identify", "allowed in calibration templates only");
}

}  // namespace
}  // namespace volcomp::config
