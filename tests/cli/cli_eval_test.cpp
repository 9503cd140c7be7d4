// `volcomp eval --at ... --json` against the worked examples of docs/model-file.md ("What the model
// computes"), tool override, directions, travel warnings, D-H chains and non-convergence.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

using Json = nlohmann::json;

// Parses stdout, which must be exactly one JSON object with the contract's keys.
Json parseOutput(const CliRun& run, bool chain = false) {
  Json j;
  EXPECT_NO_THROW(j = Json::parse(run.out)) << run.out;
  EXPECT_TRUE(j.is_object());
  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  std::sort(keys.begin(), keys.end());
  const std::vector<std::string> expected =
      chain
          ? std::vector<std::string>{"T_actual", "T_nominal", "angular_error", "error", "position"}
          : std::vector<std::string>{"angular_error", "error", "offset", "position"};
  EXPECT_EQ(keys, expected) << run.out;
  return j;
}

void expectVector(const Json& v, double x, double y, double z, double tolerance) {
  ASSERT_TRUE(v.is_array() && v.size() == 3) << v;
  EXPECT_NEAR(v[0].get<double>(), x, tolerance) << v;
  EXPECT_NEAR(v[1].get<double>(), y, tolerance) << v;
  EXPECT_NEAR(v[2].get<double>(), z, tolerance) << v;
}

TEST(CliEval, WorkedExampleGantryPitch) {
  TempDir dir;
  const std::string model = dir.write("fxyz.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "tool": [0, 0, 100], "error_units": {"angle": "urad"},
    "components": {"EBX": 100}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 200,50,-30 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const Json j = parseOutput(run);
  expectVector(j["position"], 200, 50, -30, 0.0);
  // All axes carry the tool: the X carriage's pitch b = 1e-4 rad about Y turns the lever
  // r = (0, y, z + 100) = (0, 50, 70) into Ry(b) r, so E = (70 sin b, 0, 70 (cos b - 1))
  // = (+0.007, 0, -3.5e-7) mm (spec worked example 1).
  const double b = 1e-4;
  expectVector(j["error"], 70 * std::sin(b), 0, 70 * (std::cos(b) - 1), 1e-12);
  expectVector(j["error"], 0.007, 0, -3.5e-7, 1e-9);
  expectVector(j["angular_error"], 0, b, 0, 1e-15);
  // First order o = -E; the exact solve differs by O(b^2 * 70) ~ 1e-10 mm.
  expectVector(j["offset"], -0.007, 0, 3.5e-7, 1e-9);
}

TEST(CliEval, WorkedExampleTableTilts) {
  TempDir dir;
  const std::string model = dir.write("xyfz.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "tool": [0, 0, 100], "error_units": {"length": "um", "angle": "urad"},
    "components": {"EBX": 100}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 200,50,-30 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const Json j = parseOutput(run);
  // The table carries the workpiece and tilts: H_FW^-1 = Ry(-b) Trans(x e_x + y e_y), tool point
  // in F = (0, 0, z + 100) = (0, 0, 70), so p = Ry(-b) (200, 50, 70)
  // = (200 cos b - 70 sin b, 50, 200 sin b + 70 cos b) and p0 = (200, 50, 70):
  // E = (200 (cos b - 1) - 70 sin b, 0, 200 sin b + 70 (cos b - 1)) ~ (-0.007001, 0, 0.01999965).
  const double b = 1e-4;
  expectVector(j["error"], 200 * (std::cos(b) - 1) - 70 * std::sin(b), 0,
               200 * std::sin(b) + 70 * (std::cos(b) - 1), 1e-12);
  expectVector(j["error"], -0.007001, 0, 0.019999650, 1e-9);
}

TEST(CliEval, WorkedExampleSquarenessAndPositioningTable) {
  TempDir dir;
  const std::string model = dir.write("sq.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "error_units": {"length": "um", "angle": "urad"},
    "components": {"EC0Y": 100, "EXX": {"positions": [0, 100, 200, 300],
                                        "values": [0, 5, 10, 20], "interpolation": "linear"}}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 250,100,0 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const Json j = parseOutput(run);
  // EXX(250) = 15 um; Y runs along d_Y = Rz(c) e_y = (-sin c, cos c, 0), c = 1e-4, so y = 100
  // adds (-100 sin c, 100 (cos c - 1), 0) = (-0.01, -5e-7, 0): E = (0.005, -5e-7, 0) mm.
  expectVector(j["error"], 0.005, -5e-7, 0, 1e-9);
  // o solves o + E(q + o) = 0; EXX's slope there is 1e-4, so o_x = -0.005 / 1.0001 = -0.0049995.
  expectVector(j["offset"], -0.0049995, 5e-7, 0, 1e-9);
}

TEST(CliEval, ToolOptionOverridesTheModelsTool) {
  TempDir dir;
  const std::string model = dir.write("fxyz.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "tool": [0, 0, 500], "error_units": {"angle": "urad"},
    "components": {"EBX": 100}})");
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --at 200,50,-30 --tool 0,0,100 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  // Same lever as worked example 1 once the tool is [0, 0, 100]: E = (0.007, 0, -3.5e-7).
  const Json j = parseOutput(run);
  expectVector(j["error"], 0.007, 0, -3.5e-7, 1e-9);
  expectVector(j["offset"], -0.007, 0, 3.5e-7, 1e-9);
}

TEST(CliEval, DirectionSelectsTheCurveOfABidirectionalTable) {
  TempDir dir;
  const std::string model = dir.write("bi.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "error_units": {"length": "um"},
    "components": {"EXX": {"positions": [0, 100], "values": [0, 10],
                           "values_negative": [4, 14]}}})");
  // At x = 50: positive curve 5 um, negative 9 um, unknown direction the mean 7 um.
  const struct {
    const char* option;
    double expectedMm;
  } cases[] = {{"--direction +,0,0", 0.005}, {"--direction -,+,-", 0.009}, {"", 0.007}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.option);
    const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 50,0,0 --json " + c.option);
    ASSERT_EQ(run.status, 0) << run.err;
    expectVector(parseOutput(run)["error"], c.expectedMm, 0, 0, 1e-12);
  }
}

TEST(CliEval, OutsideTheTravelWarnsOnStderr) {
  TempDir dir;
  const std::string model = dir.write("t.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "travel": {"X": [0, 100]},
    "components": {"EXX": {"positions": [0, 100], "values": [0, 0.01]}}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 150,0,0 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("warning: outside the travel (X [0, 100] mm)"), std::string::npos)
      << run.err;
  // Evaluated at the end of the travel: EXX(100) = 0.01 mm.
  expectVector(parseOutput(run)["error"], 0.01, 0, 0, 1e-12);
}

TEST(CliEval, ReadableTableWithoutJson) {
  TempDir dir;
  const std::string model = dir.write("fxyz.json", R"({"format": "volcomp-model/1",
    "name": "gantry", "topology": "FXYZ", "components": {"EXX": 0.25}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 1,2,3");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("gantry (FXYZ)"), std::string::npos) << run.out;
  // On screen in um to 4 significant digits (EXX = 0.25 mm).
  EXPECT_NE(run.out.find("error          250, 0, 0  um"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("offset         -250, 0, 0  um (converged"), std::string::npos) << run.out;
}

TEST(CliEval, DhChain) {
  TempDir dir;
  const std::string model = dir.write("arm.json", R"({"format": "volcomp-model/1",
    "chain": {"convention": "dh", "links": [
      {"joint": "revolute", "theta": 0, "d": 0, "a": 100, "alpha": 0, "dtheta": 0.01},
      {"joint": "prismatic", "theta": 0, "d": 0, "a": 0, "alpha": 0, "dd": 0.005}]}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 90,20 --json");
  ASSERT_EQ(run.status, 0) << run.err;
  const Json j = parseOutput(run, true);
  EXPECT_EQ(j["position"], Json::array({90.0, 20.0}));  // echoes --at as given (deg, mm)
  // A_1 = Rz(theta) Trans(100, 0, 0): the link end is at 100 (cos theta, sin theta, 0); the
  // prismatic joint adds d = 20 (+ dd = 0.005 actual) along z. With theta = 90 deg nominal and
  // 90.01 deg actual: E = (100 (cos 90.01 - cos 90), 100 (sin 90.01 - 1), 0.005) mm, and
  // R_nominal^T R_actual = Rz(0.01 deg): angular error (0, 0, 0.01 pi / 180) rad.
  const double deg = std::numbers::pi / 180;
  expectVector(j["error"], 100 * (std::cos(90.01 * deg) - std::cos(90 * deg)),
               100 * (std::sin(90.01 * deg) - 1), 0.005, 1e-12);
  expectVector(j["angular_error"], 0, 0, 0.01 * deg, 1e-15);
  ASSERT_EQ(j["T_nominal"].size(), 4u);
  ASSERT_EQ(j["T_actual"][3].size(), 4u);
  EXPECT_NEAR(j["T_nominal"][1][3].get<double>(), 100, 1e-12);
  EXPECT_NEAR(j["T_nominal"][2][3].get<double>(), 20, 1e-12);
  EXPECT_NEAR(j["T_actual"][2][3].get<double>(), 20.005, 1e-12);
  EXPECT_EQ(j["T_actual"][3], Json::array({0.0, 0.0, 0.0, 1.0}));
}

TEST(CliEval, DhChainNeedsOneValuePerJoint) {
  TempDir dir;
  const std::string model = dir.write("arm.json", R"({"format": "volcomp-model/1",
    "chain": {"links": [{"joint": "revolute", "theta": 0, "d": 0, "a": 100, "alpha": 0}]}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 90,20,3 --json");
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("expected 1 comma-separated numbers"), std::string::npos) << run.err;
}

TEST(CliEval, FirstOrderModeAgreesWithExactForRealisticErrors) {
  TempDir dir;
  const std::string model = dir.write("xyfz.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "tool": [0, 0, 100], "error_units": {"length": "um", "angle": "urad"},
    "components": {"EBX": 100, "EAY": -80, "ECZ": 50, "EXX": 12, "EC0Y": 30}})");
  const CliRun exact = runCli(dir, "eval " + quoted(model) + " --at 200,50,-30 --json");
  const CliRun first =
      runCli(dir, "eval " + quoted(model) + " --at 200,50,-30 --json --mode first-order");
  ASSERT_EQ(exact.status, 0) << exact.err;
  ASSERT_EQ(first.status, 0) << first.err;
  // Spec section 4: small-angle evaluation agrees with the exact model within 1e-6 mm for
  // |angles| < 1e-3 rad and arms < 2 m.
  const Json e = parseOutput(exact)["error"];
  expectVector(parseOutput(first)["error"], e[0].get<double>(), e[1].get<double>(),
               e[2].get<double>(), 1e-6);
}

TEST(CliEval, ChainsTakeNoPointsFile) {
  TempDir dir;
  const std::string model = dir.write("arm.json", R"({"format": "volcomp-model/1",
    "chain": {"links": [{"joint": "revolute", "theta": 0, "d": 0, "a": 100, "alpha": 0}]}})");
  const std::string in = dir.write("in.csv", "x,y,z\n1,2,3\n");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " +
                                     quoted((dir.path() / "o.csv").string()));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("apply to 3-axis models, not to D-H chains"), std::string::npos)
      << run.err;
}

TEST(CliEval, NonConvergedOffsetIsReportedWithStatus3) {
  TempDir dir;
  // p(x) = x + EXX(x) with EXX rising 3 mm per mm: the fixed point o <- o + p0 - p(q + o) of the
  // spec has slope -3 there and cannot converge; the result must say so, not pass silently.
  const std::string model = dir.write("steep.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "components": {"EXX": {"positions": [0, 1], "values": [0, 3]}}})");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at 0.5,0,0 --json");
  EXPECT_EQ(run.status, 3);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("did not converge"), std::string::npos) << run.err;
  parseOutput(run);
}

}  // namespace
}  // namespace volcomp::testing
