// Calibration end to end, as a metrologist would do it: volcomp-sim's TRUE machine
// (config/examples/vmc-xyfz-21-true.json) is measured and calibrated with the example template
// by the shared simulated calibration (tests/testutil/simulated_calibration.hpp: a grid in its
// travel, four tool offsets, 0.5 um Gaussian noise per coordinate, X's reversal in a second
// stage); volcompd then compensates the simulated TRUE machine with the calibrated model over
// Modbus TCP. The simulator's report must show the RMS error reduced to at most 10 %.

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "process_fixture.hpp"
#include "simulated_calibration.hpp"

namespace volcomp::e2e {
namespace {

/// Piecewise-linear interpolation of a table of the true model (its EXX and EZZ are linear).
double interpolate(const json& table, const char* values, double q) {
  const auto& p = table["positions"];
  const auto& v = table[values];
  if (q <= p.front().get<double>()) return v.front().get<double>();
  for (std::size_t i = 1; i < p.size(); ++i) {
    const double p0 = p[i - 1].get<double>(), p1 = p[i].get<double>();
    if (q <= p1) {
      const double f = (q - p0) / (p1 - p0);
      return (1 - f) * v[i - 1].get<double>() + f * v[i].get<double>();
    }
  }
  return v.back().get<double>();
}

class CalibrationPipeline : public ProcessTest {
 protected:
  testutil::CalibrationBench bench_{VOLCOMP_CLI_PATH, kExamplesDir, dir_};
};

TEST_F(CalibrationPipeline, CalibratedModelRemovesAtLeast90PercentOfTheTrueError) {
  const testutil::CalibratedExample files = testutil::calibrateExampleMachine(bench_);
  ASSERT_FALSE(HasFailure());
  const json stage1 = bench_.readJson(files.stage1);
  const json report = bench_.readJson(files.report);
  const json calibrated = bench_.readJson(files.model);
  const std::string& calibratedFile = files.model;

  // --- The report has what a calibration report must have.
  EXPECT_EQ(report["format"], "volcomp-calibration-report/1");
  const std::size_t n = report["parameter_count"].get<std::size_t>();
  ASSERT_EQ(report["parameters"].size(), n);
  // The template: per axis 4 tables (positioning and 3 angles) on 11 (X), 6 (Y), 6 (Z) nodes
  // = 44 + 24 + 24, 6 straightness polynomials c2..c6 = 30, 3 squareness constants.
  EXPECT_EQ(n, 44U + 24U + 24U + 30U + 3U);
  // A parameter the data do not determine has no sigma and no correlations.
  std::vector<bool> identifiable;
  for (const json& p : report["parameters"]) {
    EXPECT_TRUE(p["name"].is_string());
    EXPECT_TRUE(p["value"].is_number()) << p.dump();
    EXPECT_TRUE(p["identifiable"].is_boolean()) << p.dump();
    identifiable.push_back(p["identifiable"].get<bool>());
    EXPECT_EQ(p["std"].is_number(), identifiable.back()) << p.dump();
    EXPECT_EQ(p["std"].is_null(), !identifiable.back()) << p.dump();
  }
  const json& correlation = report["correlation"];
  ASSERT_EQ(correlation.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(correlation[i].size(), n);
    if (identifiable[i]) {
      EXPECT_NEAR(correlation[i][i].get<double>(), 1.0, 1e-9) << i;
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (!identifiable[i] || !identifiable[j]) {
        EXPECT_TRUE(correlation[i][j].is_null() && correlation[j][i].is_null()) << i << ", " << j;
        continue;
      }
      EXPECT_NEAR(correlation[i][j].get<double>(), correlation[j][i].get<double>(), 1e-9);
      EXPECT_LE(std::abs(correlation[i][j].get<double>()), 1.0 + 1e-9);
    }
  }
  const json& before = report["residuals"]["before"];
  const json& after = report["residuals"]["after"];
  for (const json* r : {&before, &after}) {
    EXPECT_TRUE((*r)["rms_mm"].is_number());
    EXPECT_TRUE((*r)["max_mm"].is_number());
  }
  EXPECT_GT(before["rms_mm"].get<double>(), 0.010) << "the true error is ~16 um RMS on the grid";
  // After the fit only the noise should be left: |e| of 3 independent N(0, 0.5 um) coordinates
  // has RMS 0.5 um * sqrt(3) = 0.866 um; a few % more for what the template's tables and
  // polynomials cannot follow of the true shapes (linear tables with kinks every 50 mm).
  EXPECT_GT(after["rms_mm"].get<double>(), 0.80e-3);
  EXPECT_LT(after["rms_mm"].get<double>(), 0.95e-3);
  // s0 per weighted row is the noise per coordinate.
  EXPECT_NEAR(report["s0_mm"].get<double>(), testutil::kMeasurementNoiseMm,
              0.1 * testutil::kMeasurementNoiseMm);
  EXPECT_TRUE(report["condition_number"].is_number());
  EXPECT_GT(report["condition_number"].get<double>(), 1.0);
  const int rank = report["rank"].get<int>();
  EXPECT_LT(rank, static_cast<int>(n));
  EXPECT_EQ(report["unidentifiable"].size(), n - static_cast<std::size_t>(rank));
  // Every parameter flagged not identifiable is named in a combination, and no other.
  std::set<std::string> named;
  for (const json& u : report["unidentifiable"]) {
    for (const json& name : u["parameters"]) named.insert(name.get<std::string>());
  }
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(named.count(report["parameters"][i]["name"].get<std::string>()) == 1,
              !identifiable[i])
        << report["parameters"][i].dump();
  }
  // The written model records where it comes from and the tools it was measured with.
  ASSERT_TRUE(stage1.contains("calibration"));
  EXPECT_EQ(stage1["calibration"]["tools_mm"].size(), testutil::kMeasurementTools.size());
  EXPECT_EQ(stage1["calibration"]["rank"], rank);
  EXPECT_EQ(stage1["calibration"]["not_identifiable"].size(), named.size());
  // The constant rolls of the X and Y carriages cannot be separated: both carry the table, and
  // a constant rotation about X of either turns the tool point relative to the table, r, into
  // the same displacement (a + b) e_x x r at every point and tool; unlike a pitch or yaw of Y,
  // a roll of Y leaves the direction of X's travel (e_x) unchanged. Only a + b is seen.
  bool rollsTogether = false;
  for (const json& u : report["unidentifiable"]) {
    EXPECT_TRUE(u["description"].is_string());
    ASSERT_FALSE(u["parameters"].empty());
    bool x = false, y = false;
    for (const json& name : u["parameters"]) {
      x = x || name.get<std::string>().rfind("EAX", 0) == 0;
      y = y || name.get<std::string>().rfind("EAY", 0) == 0;
    }
    rollsTogether = rollsTogether || (x && y);
  }
  EXPECT_TRUE(rollsTogether) << report["unidentifiable"].dump(1);

  // --- The positioning errors are identified as they are: they are the only translations
  // along their own axes in this template (straightness polynomials start at q^2), so the
  // node values must match the true curves within the noise (std ~0.06 um) and the fit of a
  // cubic spline on 85/100 mm nodes to tables with kinks every 50 mm (< 0.1 um).
  const json truth = bench_.readJson(bench_.trueModel());
  for (const char* name : {"EXX", "EYY", "EZZ"}) {
    const json& fitted = calibrated["components"][name];
    for (std::size_t i = 0; i < fitted["positions"].size(); ++i) {
      const double q = fitted["positions"][i].get<double>();
      // EYY is a quadratic-element table whose nodes include every template node (0, 100, ...):
      // at a node every interpolation is the node value, so linear interpolation is exact there.
      const double expectedUm = interpolate(truth["components"][name], "values", q);
      EXPECT_NEAR(fitted["values"][i].get<double>(), expectedUm, 0.3) << name << " at " << q;
      if (std::string(name) == "EXX") {
        const double reverseUm = interpolate(truth["components"][name], "values_negative", q);
        EXPECT_NEAR(fitted["values_negative"][i].get<double>(), reverseUm, 0.3)
            << "EXX reverse at " << q;
      }
    }
  }

  // --- The calibrated model compensates the simulated TRUE machine. The path: the four body
  // diagonals of a box inside the measured volume, joined by X-reversing moves, so that every
  // axis reverses and Z varies; 400 mm/s (24 m/min).
  json sim = simConfig(bench_.trueModel());
  sim["path"] = {{"type", "points"},
                 {"feed_mm_min", 24000},
                 {"points",
                  {{100, 100, -400},
                   {750, 400, -100},
                   {100, 400, -400},
                   {750, 100, -100},
                   {100, 100, -100},
                   {750, 400, -400},
                   {100, 400, -100},
                   {750, 100, -400}}}};
  const Listening at = startSim(sim, {"--port", "0", "--duration", "8"});
  ASSERT_EQ(at.kind, "tcp");
  startDaemon(daemonConfig(at, calibratedFile));
  const json result = finishSim(/*sendQuit=*/false);
  ASSERT_TRUE(result.is_object()) << daemonLog();
  stopDaemon();

  EXPECT_EQ(result["limiter_violations"], 0) << result["first_violation"];
  EXPECT_EQ(result["sessions"], 1);
  ASSERT_GT(result["samples"].get<int>(), 5000);
  const double un = result["rms_uncompensated_um"].get<double>();
  const double comp = result["rms_compensated_um"].get<double>();
  EXPECT_GT(un, 5.0) << result.dump();
  EXPECT_LE(comp, 0.10 * un) << result.dump();
  std::cerr << "RMS uncompensated " << un << " um, compensated " << comp << " um; max "
            << result["max_uncompensated_um"] << " / " << result["max_compensated_um"] << " um\n";
}

}  // namespace
}  // namespace volcomp::e2e
