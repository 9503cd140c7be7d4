// The readers of the report's inputs: what is present is read, what is absent stays absent, a
// field of the wrong type is skipped with a note naming file and key, and a document of the wrong
// kind is refused with a ConfigError.

#include <gtest/gtest.h>

#include <filesystem>

#include "temp_files.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {
namespace {

using nlohmann::json;
const std::filesystem::path kData = VOLCOMP_REPORT_TEST_DATA;

bool mentions(const Notes& notes, const std::string& fragment) {
  for (const std::string& n : notes) {
    if (n.find(fragment) != std::string::npos) return true;
  }
  return false;
}

// As `volcomp calibrate --report` writes it (calibration/src/report.cpp), two parameters.
json calibrationDocument() {
  return json::parse(R"({
    "format": "volcomp-calibration-report/1", "template": "t.json", "measurements": "m.csv",
    "method": "linear", "loss": "none", "points": 25, "converged": true, "iterations": 3,
    "termination": "step below tolerance",
    "parameters": [
      {"name": "EXX c1", "key": "components.EXX", "unit": "um/mm", "value": 0.0183, "std": 0.0004,
       "start": 0, "identifiable": true, "nuisance": false},
      {"name": "EC0Y", "key": "components.EC0Y", "unit": "urad", "value": 18.2, "std": null,
       "start": 0, "identifiable": false, "nuisance": false}],
    "correlation": [[1, 0.3], [0.3, 1]],
    "residuals": {"before": {"rms_mm": 0.0142, "max_mm": 0.031, "max_line": 7},
                  "after": {"rms_mm": 0.0004, "max_mm": 0.0012, "max_line": 12,
                            "per_axis": {"x_mm": 0.0002}}},
    "rank": 1, "parameter_count": 2, "rank_tolerance": 1e-7, "condition_number": 12.5,
    "full_condition_number": null, "singular_values": [1.0, 0.0], "rows": 75, "dof": 74,
    "s0_mm": 0.0004,
    "unidentifiable": [{"parameters": ["EC0Y"], "coefficients": [1.0],
                        "relative_singular_value": 0.0, "description": "EC0Y is not seen"}],
    "validation": {"rms_mm": 0.0005}, "tools": 4})");
}

TEST(CalibrationReportReader, ReadsWhatCalibrateWrites) {
  Notes notes;
  const CalibrationReport r = readCalibrationReport(calibrationDocument(), "cal.json", notes);
  EXPECT_TRUE(notes.empty()) << notes.front();
  EXPECT_EQ(r.templateFile, "t.json");
  EXPECT_EQ(r.measurementFile, "m.csv");
  EXPECT_EQ(r.points, 25);
  EXPECT_EQ(r.rank, 1);
  EXPECT_EQ(r.parameterCount, 2);
  ASSERT_EQ(r.parameters.size(), 2U);
  EXPECT_EQ(r.parameters[0].name, "EXX c1");
  EXPECT_EQ(r.parameters[0].unit, "um/mm");
  EXPECT_DOUBLE_EQ(*r.parameters[0].value, 0.0183);
  EXPECT_DOUBLE_EQ(*r.parameters[0].sigma, 0.0004);
  EXPECT_FALSE(r.parameters[1].sigma.has_value());  // null: no sigma for an unidentifiable one
  EXPECT_FALSE(*r.parameters[1].identifiable);
  ASSERT_EQ(r.correlation.size(), 4U);
  EXPECT_DOUBLE_EQ(r.correlation[1], 0.3);
  EXPECT_DOUBLE_EQ(*r.before.rmsMm, 0.0142);
  EXPECT_EQ(r.after.maxLine, 12);
  ASSERT_EQ(r.after.more.size(), 1U);
  EXPECT_EQ(r.after.more[0].first, "per_axis.x_mm");
  ASSERT_EQ(r.unidentifiable.size(), 1U);
  EXPECT_EQ(r.unidentifiable[0], "EC0Y is not seen");
  // What a newer calibrate adds is listed, not lost.
  bool validation = false, tools = false;
  for (const Figure& f : r.otherFields) {
    validation = validation || (f.key == "validation.rms_mm" && f.text == "0.0005");
    tools = tools || (f.key == "tools" && f.text == "4");
  }
  EXPECT_TRUE(validation);
  EXPECT_TRUE(tools);
}

TEST(CalibrationReportReader, SkipsAFieldOfTheWrongTypeWithANote) {
  json document = calibrationDocument();
  document["residuals"]["after"]["rms_mm"] = "small";
  document["parameters"][0]["std"] = json::array({1});
  document["correlation"] = json::array({json::array({1, 0.3})});
  Notes notes;
  const CalibrationReport r = readCalibrationReport(document, "cal.json", notes);
  EXPECT_FALSE(r.after.rmsMm.has_value());
  EXPECT_FALSE(r.parameters[0].sigma.has_value());
  EXPECT_TRUE(r.correlation.empty());
  EXPECT_TRUE(mentions(notes, "cal.json: residuals.after.rms_mm: expected a number"));
  EXPECT_TRUE(mentions(notes, "cal.json: parameters[0].std: expected a number"));
  EXPECT_TRUE(mentions(notes, "cal.json: correlation: 1 rows for 2 parameters"));
}

TEST(CalibrationReportReader, RefusesOtherDocumentsAndNotesNewerFormats) {
  Notes notes;
  EXPECT_THROW(
      readCalibrationReport(json::parse(R"({"format": "volcomp-model/1"})"), "m.json", notes),
      config::ConfigError);
  EXPECT_THROW(readCalibrationReport(json::parse("[1, 2]"), "a.json", notes), config::ConfigError);
  json newer = calibrationDocument();
  newer["format"] = "volcomp-calibration-report/2";
  readCalibrationReport(newer, "cal.json", notes);
  EXPECT_TRUE(mentions(notes, "volcomp-calibration-report/2 is newer"));
}

TEST(RunSummaryReader, ReadsTheSimulatorsLine) {
  Notes notes;
  const RunSummary run = loadRunSummary((kData / "run-summary.json").string(), notes);
  EXPECT_TRUE(notes.empty());
  ASSERT_TRUE(run.total.rmsBefore && run.total.rmsAfter);
  EXPECT_GT(*run.total.rmsBefore, 5 * *run.total.rmsAfter);
  for (const ErrorStats& axis : run.axes) EXPECT_TRUE(axis.rmsBefore && axis.maxAfter);
  EXPECT_EQ(run.limiterViolations, 0);
  EXPECT_GT(run.writes.value_or(0), 100);
  EXPECT_EQ(run.positionSemantics, "commanded");
  ASSERT_TRUE(run.appliedOffsetMm.has_value());
}

TEST(RunSummaryReader, TakesTheSnapshotWhileCompensatingAndCapturedStdout) {
  std::string line = R"({"rms_uncompensated_um": 14.0, "rms_compensated_um": 3.0, "writes": 10,
    "limiter_violations": 0, "compensating": {"rms_uncompensated_um": 14.3,
    "rms_compensated_um": 0.94, "axes": {"X": {"rms_uncompensated_um": 4.5}}},
    "daemon": {"cycles": 1163, "overruns": 1, "exit_status": 0}})";
  for (char& c : line) {
    if (c == '\n') c = ' ';
  }
  testing::TempDir dir;
  const std::string file = dir.write("stdout.txt", "LISTENING tcp 127.0.0.1 5020\n" + line + "\n");
  Notes notes;
  const RunSummary run = loadRunSummary(file, notes);
  EXPECT_TRUE(run.whileCompensating);
  EXPECT_DOUBLE_EQ(*run.total.rmsAfter, 0.94);
  EXPECT_DOUBLE_EQ(*run.axes[0].rmsBefore, 4.5);
  EXPECT_EQ(run.daemonCycles, 1163);
  EXPECT_EQ(run.daemonExitStatus, 0);
  EXPECT_THROW(loadRunSummary(dir.write("x.json", R"({"writes": 3})"), notes), config::ConfigError);
  EXPECT_THROW(loadRunSummary(dir.write("y.txt", "no json here\n"), notes), config::ConfigError);
}

TEST(RecordedWrites, ReadsTheRecordAndNamesABadLine) {
  testing::TempDir dir;
  const std::string good =
      dir.write("w.csv",
                "t_s,offset_x_mm,offset_y_mm,offset_z_mm,status,heartbeat,partial,violation\n"
                "0.01,0.001,-0.002,0.003,1,1,0,0\n0.02,0.002,-0.002,0.003,1,2,0,1\n");
  const std::vector<RecordedWrite> writes = loadRecordedWrites(good);
  ASSERT_EQ(writes.size(), 2U);
  EXPECT_DOUBLE_EQ(writes[1].offsetMm[0], 0.002);
  EXPECT_FALSE(writes[0].violation);
  EXPECT_TRUE(writes[1].violation);
  const std::string bad = dir.write(
      "b.csv", "t_s,offset_x_mm,offset_y_mm,offset_z_mm,violation\n0.01,0,0,0,0\n0.02,x,0,0,0\n");
  try {
    loadRecordedWrites(bad);
    FAIL() << "a bad row was accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "line 3");
  }
  EXPECT_THROW(loadRecordedWrites(dir.write("h.csv", "x,y,z\n1,2,3\n")), config::ConfigError);
}

TEST(IsoAxisReader, ReadsEveryTargetAndFigureInMicrometres) {
  Notes notes;
  const IsoAxis x = loadIsoAxis((kData / "iso230-2-x.json").string(), notes);
  EXPECT_TRUE(notes.empty());
  EXPECT_EQ(x.axis, model::Axis::X);
  EXPECT_EQ(x.runsUp, 5);
  EXPECT_EQ(x.runsDown, 5);
  ASSERT_EQ(x.targets.size(), 11U);
  EXPECT_EQ(x.targets[0].runsUp.size(), 5U);
  EXPECT_TRUE(x.targets[3].meanUp && x.targets[3].sDown && x.targets[3].repeat);
  ASSERT_EQ(x.figures.size(), 12U);
  EXPECT_EQ(x.figures.front().symbol, "B");
  EXPECT_EQ(x.figures.back().symbol, "A");
  // The document's lengths are mm; the report's deviations are µm.
  const json document = readJsonFile((kData / "iso230-2-x.json").string());
  EXPECT_DOUBLE_EQ(*x.targets[0].meanUp,
                   document["targets"][0]["mean_positive"].get<double>() * 1e3);
  EXPECT_DOUBLE_EQ(x.figures.back().valueUm,
                   document["axis_figures"]["accuracy_bidirectional"].get<double>() * 1e3);
}

TEST(IsoAxisReader, AnAxisThatIsNoneOfXYZIsNotedAndLeftOut) {
  Notes notes;
  const IsoAxis w = readIsoAxis(
      json::parse(R"({"format": "volcomp-iso230-2/1", "axis": "W", "targets": [{"position": 0}]})"),
      "w.json", notes);
  EXPECT_FALSE(w.axis);
  ASSERT_EQ(notes.size(), 1U);
  EXPECT_EQ(notes[0], "w.json: axis: expected X, Y or Z, got \"W\"; not shown");
  notes.clear();
  const IsoAxis none = readIsoAxis(
      json::parse(
          R"({"format": "volcomp-iso230-2/1", "axis": null, "targets": [{"position": 0}]})"),
      "n.json", notes);
  EXPECT_FALSE(none.axis);
  EXPECT_TRUE(notes.empty());
}

TEST(IsoAxisReader, StatedUnitsAreConvertedAndOtherDocumentsRefused) {
  Notes notes;
  const IsoAxis um = readIsoAxis(json::parse(R"({"format": "volcomp-iso230-2/1", "axis": "Y",
    "units": {"position": "m", "deviation": "um"},
    "targets": [{"position": 0.25, "mean_positive": 1.5}], "axis_figures": {"reversal": 2}})"),
                                 "y.json", notes);
  EXPECT_EQ(um.axis, model::Axis::Y);
  ASSERT_EQ(um.targets.size(), 1U);
  EXPECT_DOUBLE_EQ(um.targets[0].positionMm, 250.0);
  EXPECT_DOUBLE_EQ(*um.targets[0].meanUp, 1.5);
  EXPECT_DOUBLE_EQ(um.figures[0].valueUm, 2.0);
  EXPECT_THROW(readIsoAxis(json::parse(R"({"axis": "X", "targets": []})"), "i.json", notes),
               config::ConfigError);
  EXPECT_THROW(readIsoAxis(json::parse(R"({"format": "volcomp-iso230-2/1",
    "units": {"deviation": "furlong"}})"),
                           "i.json", notes),
               config::ConfigError);
}

}  // namespace
}  // namespace volcomp::report
