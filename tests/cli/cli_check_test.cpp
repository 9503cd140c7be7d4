// `volcomp check`: a valid file gives status 0 and a summary of what it holds.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

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

// The most common mistake when typing laser data: the numbers in um, the file saying mm.
constexpr const char* kTypedAsMm = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "mm", "angle": "urad"},
  "components": {"EXX": {"positions": [0, 425, 850], "values": [0, 8.7, 15.6]}}})";
constexpr const char* kInUm = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "um", "angle": "urad"},
  "components": {"EXX": {"positions": [0, 425, 850], "values": [0, 8.7, 15.6]}}})";

TEST(CliCheck, RefusesMicrometresTypedAsMillimetresInOneLine) {
  TempDir dir;
  const CliRun run = runCli(dir, "check " + quoted(dir.write("mm.json", kTypedAsMm)));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.errLines(), 1) << run.err;
  expectContains(run.err, "mm.json: components.EXX");
  expectContains(run.err, "implausible for a machine tool");
  expectContains(run.err, "Were values in um entered as mm?");
}

TEST(CliCheck, RefusesAModelWithoutErrorUnits) {
  TempDir dir;
  const CliRun run = runCli(dir, "check " + quoted(dir.write("n.json", R"({"format":
    "volcomp-model/1", "topology": "FXYZ", "components": {"EXX": 0.002}})")));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  expectContains(run.err, "n.json: error_units");
}

TEST(CliCheck, OffsetsMustFitMaxOffsetOrTheDaemonsLimiter) {
  TempDir dir;
  const std::string model = dir.write("um.json", kInUm);
  const CliRun tight = runCli(dir, "check --max-offset 0.01 " + quoted(model));
  EXPECT_EQ(tight.status, 2);
  EXPECT_EQ(tight.errLines(), 1) << tight.err;
  expectContains(tight.err, "the model asks for an offset of 15.6");
  expectContains(tight.err, "(--max-offset)");
  const CliRun wide = runCli(dir, "check --max-offset 0.1 " + quoted(model));
  ASSERT_EQ(wide.status, 0) << wide.err;
  expectContains(wide.out, "peak offset   X 15.6");
  expectContains(wide.out, "offsets <= 100 um (--max-offset)");

  const std::string config =
      dir.write("d.json", R"({"model": "um.json", "position_semantics": "commanded",
    "limiter": {"max_offset_mm": 0.012, "max_rate_mm_s": 0.5},
    "transport": {"type": "modbus-tcp", "host": "127.0.0.1", "port": 1502, "registers": {
      "position": {"X": {"address": 0}, "Y": {"address": 2}, "Z": {"address": 4}},
      "enable": {"address": 6, "bit": 0}, "homed": {"address": 6, "bit": 1},
      "offset": {"X": {"address": 14}, "Y": {"address": 16}, "Z": {"address": 18}},
      "status": 20, "heartbeat": 21}}})");
  const CliRun limiter = runCli(dir, "check --config " + quoted(config) + " " + quoted(model));
  EXPECT_EQ(limiter.status, 2);
  expectContains(limiter.err, "limiter.max_offset_mm of " + config);
}

TEST(CliCheck, PrintsEachAxisSideAndTheReadableAssessment) {
  TempDir dir;
  const CliRun run = runCli(dir, "check " + quoted(dir.write("um.json", kInUm)));
  ASSERT_EQ(run.status, 0) << run.err;
  expectContains(run.out,
                 "sides       X workpiece side (moves the workpiece): its motion errors "
                 "= -(reading of the tool relative to the workpiece)");
  expectContains(run.out,
                 "            Z tool side (moves the tool): its motion errors = "
                 "+(reading of the tool relative to the workpiece)");
  expectContains(run.out, "squareness and grids = +reading on either side");
  expectContains(run.out, "plausible   over 21 x 21 x 21 points of X [0, 850]");
  expectContains(run.out, "peak |E|      15.6 um");
  expectContains(run.out,
                 "limits        values and |E| <= 1000 um, angles <= 10000 urad (defaults)");
  const CliRun arcsec =
      runCli(dir, "check --angle-unit arcsec " + quoted((dir.path() / "um.json").string()));
  ASSERT_EQ(arcsec.status, 0) << arcsec.err;
  expectContains(arcsec.out, "angles <= 2063 arcsec (defaults)");
}

TEST(CliCheck, PrintsTheSchemaOfTheFormat) {
  TempDir dir;
  const CliRun run = runCli(dir, "check --schema");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto schema = nlohmann::json::parse(run.out);
  EXPECT_EQ(schema["title"], "volcomp model file (volcomp-model/1)");
  EXPECT_EQ(schema["$defs"]["machine"]["required"],
            nlohmann::json::parse(R"(["format", "topology", "error_units"])"));
  const CliRun none = runCli(dir, "check");
  EXPECT_EQ(none.status, 2);
  expectContains(none.err, "a model file is required");
}

}  // namespace
}  // namespace volcomp::testing
