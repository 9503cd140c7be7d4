// The worked examples of docs/model-file.md, "Entering measured data", through `volcomp eval`:
// each reading entered with the sign the page gives for a tool-side (FXYZ) and a workpiece-side
// (XYFZ) axis reproduces the reading as the tool's error relative to the workpiece.

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

// `components` in um and urad for the topology; returns eval --json at `at`.
nlohmann::json evalAt(const std::string& topology, const std::string& components,
                      const std::string& at, const std::string& tool = "[0, 0, 0]") {
  TempDir dir;
  const std::string model =
      dir.write("m.json", R"({"format": "volcomp-model/1", "topology": ")" + topology +
                              R"(", "travel": {"X": [-850, 850], "Y": [-500, 500], "Z": [-500, 0]},
        "tool": )" + tool + R"(, "error_units": {"length": "um", "angle": "urad"},
        "components": {)" + components +
                              "}}");
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --at " + at + " --json");
  EXPECT_EQ(run.status, 0) << run.err;
  return nlohmann::json::parse(run.out);
}

TEST(EnteringMeasuredData, LaserPositioningTakesTheSideSign) {
  // +4.0 um at x = 100: EXX = +4 on a tool-side X, -4 on a workpiece-side X.
  for (const auto& [topology, value] : {std::pair{"FXYZ", "4.0"}, std::pair{"XYFZ", "-4.0"}}) {
    const auto r = evalAt(
        topology, R"("EXX": {"positions": [0, 100], "values": [0, )" + std::string(value) + "]}",
        "100,0,0");
    EXPECT_NEAR(r["error"][0].get<double>(), 0.004, 1e-12) << topology;
    // The offset solve sees the table's slope: o = -4 um * (1 - 4e-5) at x + o.
    EXPECT_NEAR(r["offset"][0].get<double>(), -0.004 * (1 - 4e-5), 1e-9) << topology;
  }
}

TEST(EnteringMeasuredData, StraightedgeTakesTheSideSign) {
  for (const auto& [topology, value] : {std::pair{"FXYZ", "3.0"}, std::pair{"XYFZ", "-3.0"}}) {
    const auto r = evalAt(topology,
                          R"("EYX": {"positions": [0, 400, 800], "values": [0, )" +
                              std::string(value) + R"(, 0], "interpolation": "cubic"})",
                          "400,0,0");
    EXPECT_NEAR(r["error"][1].get<double>(), 0.003, 1e-12) << topology;
  }
}

TEST(EnteringMeasuredData, ALevelOnTheCarriageIsTheComponentOnEitherSide) {
  const auto fxyz = evalAt("FXYZ", R"("EBX": {"positions": [0, 500], "values": [0, 20]})",
                           "500,0,0", "[0, 0, 100]");
  EXPECT_NEAR(fxyz["error"][0].get<double>(), 0.002, 1e-9);
  EXPECT_NEAR(fxyz["angular_error"][1].get<double>(), 20e-6, 1e-15);
  const auto xyfz = evalAt("XYFZ", R"("EBX": {"positions": [0, 500], "values": [0, 20]})",
                           "500,0,0", "[0, 0, 100]");
  EXPECT_NEAR(xyfz["error"][0].get<double>(), -0.002, 1e-6);
  EXPECT_NEAR(xyfz["error"][2].get<double>(), 0.010, 1e-6);
  EXPECT_NEAR(xyfz["angular_error"][1].get<double>(), -20e-6, 1e-15);
}

TEST(EnteringMeasuredData, BallBarSquarenessHasNoSide) {
  // R = 100 mm: EC0Y = 50 urad makes the 45 degree diagonal 2.5 um short, the 135 degree one
  // 2.5 um long, on both topologies.
  for (const char* topology : {"FXYZ", "XYFZ"}) {
    const double h = 100.0 / std::sqrt(2.0);
    const std::string at45 = std::to_string(h) + "," + std::to_string(h) + ",0";
    const std::string at135 = std::to_string(-h) + "," + std::to_string(h) + ",0";
    const auto r45 = evalAt(topology, R"("EC0Y": 50)", at45);
    const auto r135 = evalAt(topology, R"("EC0Y": 50)", at135);
    const double radial45 =
        (r45["error"][0].get<double>() + r45["error"][1].get<double>()) / std::sqrt(2.0);
    const double radial135 =
        (-r135["error"][0].get<double>() + r135["error"][1].get<double>()) / std::sqrt(2.0);
    EXPECT_NEAR(radial45, -0.0025, 1e-7) << topology;
    EXPECT_NEAR(radial135, 0.0025, 1e-7) << topology;
  }
}

}  // namespace
}  // namespace volcomp::testing
