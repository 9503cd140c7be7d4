// `volcomp check`: a valid file gives status 0 and a summary of what it holds.

#include <gtest/gtest.h>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

void expectContains(const std::string& text, const std::string& fragment) {
  EXPECT_NE(text.find(fragment), std::string::npos) << text << "\nlacks: " << fragment;
}

TEST(CliCheck, SummarisesAThreeAxisModel) {
  TempDir dir;
  const std::string model = dir.write("m.json", R"({"format": "volcomp-model/1",
    "name": "VMC", "topology": "XYFZ", "travel": {"X": [0, 850], "Z": [-500, 0]},
    "tool": [0, 0, 120], "error_units": {"length": "um", "angle": "urad"},
    "components": {
      "EXX": {"positions": [0, 400, 800], "values": [0, 6.2, -15.6], "values_negative": [4, 10, 19]},
      "EBX": {"polynomial": [0, 0.02]},
      "EYY": {"positions": [0, 250, 500], "values": [0, 3, 1], "interpolation": "quadratic"},
      "ECZ": -3.25, "EC0Y": 18.5},
    "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [0, 425, 850], "Y": [0, 500]},
               "values": [[0, 3], [5, -11], [2, 1]]}]})");
  const CliRun run = runCli(dir, "check " + quoted(model));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  expectContains(run.out, "valid volcomp-model/1");
  expectContains(run.out, "name        VMC");
  expectContains(run.out, "topology    XYFZ");
  expectContains(run.out, "travel      X [0, 850]  Y unbounded  Z [-500, 0] mm");
  expectContains(run.out, "tool        [0, 0, 120] mm");
  expectContains(run.out, "error units length um, angle urad");
  // Peaks in the file's units: max(|values|, |values_negative|) = 19 um.
  expectContains(run.out,
                 "EXX  table, linear, 3 nodes over [0, 800] mm, peak |value| 19 um, "
                 "bidirectional; note: the travel [0, 850] mm reaches beyond the table");
  // 0.02 urad/mm over X in [0, 850]: peak 17 urad at X = 850.
  expectContains(run.out,
                 "EBX  polynomial of degree 1 over the travel [0, 850] mm, peak |value| 17 urad");
  expectContains(run.out,
                 "EYY  table, quadratic, 3 nodes over [0, 500] mm, peak |value| 3 um, "
                 "one direction");
  expectContains(run.out, "ECZ  constant, value -3.25 urad");
  expectContains(run.out, "EC0Y constant, value 18.5 urad");
  expectContains(run.out,
                 "EZ over X,Y: 3 x 2 nodes, X [0, 850], Y [0, 500] mm, peak |value| 11 um");
}

TEST(CliCheck, SummarisesAChain) {
  TempDir dir;
  const std::string model = dir.write("c.json", R"({"format": "volcomp-model/1", "name": "arm",
    "chain": {"links": [
      {"joint": "revolute", "theta": 0, "d": 0, "a": 100, "alpha": 90, "dalpha": 0.001},
      {"joint": "fixed", "translation": [0, 0, 50], "drotation_deg": [0, 0.002, 0]}]}})");
  const CliRun run = runCli(dir, "check " + quoted(model));
  ASSERT_EQ(run.status, 0) << run.err;
  expectContains(run.out, "chain       standard D-H (dh), 2 links, 1 joint value(s) for --at");
  expectContains(run.out,
                 "link 1  revolute   theta 0 deg, d 0 mm, a 100 mm, alpha 90 deg; "
                 "deviations dtheta 0 deg, dd 0 mm, da 0 mm, dalpha 0.001 deg");
  expectContains(run.out,
                 "link 2  fixed      transform rotation [0, 0, 0] deg, translation "
                 "[0, 0, 50] mm; deviations rotation [0, 0.002, 0] deg");
}

TEST(CliCheck, CalibrationTemplatesNeedTheTemplateFlag) {
  TempDir dir;
  const std::string model = dir.write("t.json", R"({"format": "volcomp-model/1",
    "topology": "FXYZ", "components": {"EXX": {"identify": {"kind": "table"}}}})");
  const CliRun plain = runCli(dir, "check " + quoted(model));
  EXPECT_EQ(plain.status, 2);
  EXPECT_EQ(plain.errLines(), 1);
  expectContains(plain.err, "components.EXX.identify");
  const CliRun templ = runCli(dir, "check --template " + quoted(model));
  ASSERT_EQ(templ.status, 0) << templ.err;
  expectContains(templ.out, "identify    1 block(s)");
  expectContains(templ.out, "components.EXX: {\"kind\":\"table\"}");
}

// A model that evaluates to infinity in its travel is invalid: status 2, one line naming the
// component, not "peak |value| inf" and status 0.
TEST(CliCheck, RefusesAModelThatEvaluatesToInfinity) {
  TempDir dir;
  const std::string model = dir.write("m.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "travel": {"X": [0, 850]}, "error_units": {"length": "um", "angle": "urad"},
    "components": {"EXX": {"polynomial": [0, 0, 0, 0, 1e300]}}})");
  const CliRun run = runCli(dir, "check " + quoted(model));
  EXPECT_EQ(run.status, 2) << run.out;
  expectContains(run.err, "components.EXX");
  expectContains(run.err, "not finite");
  EXPECT_EQ(run.out.find("inf"), std::string::npos) << run.out;
}

}  // namespace
}  // namespace volcomp::testing
