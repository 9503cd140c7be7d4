// The positioning-run CSV reader and what the evaluation refuses and warns about.

#include <gtest/gtest.h>

#include <optional>
#include <sstream>

#include "volcomp/config/config_error.hpp"
#include "volcomp/metrology/iso230_2.hpp"
#include "volcomp/metrology/positioning_runs.hpp"

namespace volcomp::metrology {
namespace {

PositioningRuns parse(const std::string& text, std::optional<model::Axis> axis = std::nullopt) {
  std::istringstream in(text);
  return parsePositioningCsv(in, "runs.csv", axis);
}

std::string errorOf(const std::string& text, std::optional<model::Axis> axis = std::nullopt) {
  try {
    evaluateIso230_2(parse(text, axis));
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

/// A valid test: `runs` runs per direction at the given targets, deviation = run * 0.1 um.
std::string table(int runsUp, int runsDown, const std::vector<double>& targets,
                  const std::string& header = "run,direction,target_mm,deviation_um") {
  std::ostringstream csv;
  csv << header << '\n';
  for (int run = 1; run <= std::max(runsUp, runsDown); ++run) {
    for (double t : targets) {
      if (run <= runsUp) csv << run << ",+," << t << ',' << 0.1 * run << '\n';
      if (run <= runsDown) csv << run << ",-," << t << ',' << 1 + 0.1 * run << '\n';
    }
  }
  return csv.str();
}

const std::vector<double> kTargets{0, 21.5, 39.5, 62, 80};

TEST(RunsCsv, UnitsAndAliasesInTheHeader) {
  const PositioningRuns runs = parse(
      "# comment\n\nRun Number, Direction, Target [m], Actual (mm), Temp_C\n"
      "1, forward, 0.1, 100.0025, 20.1\n2, ↓, 0.1, 99.999, 20.2\n");
  ASSERT_EQ(runs.samples.size(), 2u);
  EXPECT_DOUBLE_EQ(runs.samples[0].targetMm, 100.0);
  EXPECT_NEAR(runs.samples[0].deviationMm, 0.0025, 1e-12);
  EXPECT_EQ(runs.samples[0].direction, model::Direction::Positive);
  EXPECT_EQ(runs.samples[1].direction, model::Direction::Negative);
  EXPECT_NEAR(runs.samples[1].deviationMm, -0.001, 1e-12);
  EXPECT_EQ(runs.samples[1].line, 5);
  EXPECT_EQ(runs.ignoredColumns, (std::vector<std::string>{"Temp_C"}));
}

TEST(RunsCsv, SemicolonsWithDecimalCommas) {
  const PositioningRuns runs = parse("Target_mm;Deviation_µm;Run;Direction\n12,5;-1,25;3;up\n");
  ASSERT_EQ(runs.samples.size(), 1u);
  EXPECT_DOUBLE_EQ(runs.samples[0].targetMm, 12.5);
  EXPECT_NEAR(runs.samples[0].deviationMm, -0.00125, 1e-15);
  EXPECT_EQ(runs.samples[0].run, 3);
}

TEST(RunsCsv, NanometresAndInches) {
  const PositioningRuns runs = parse("target_in,error_nm,run,dir\n1,250,1,+\n");
  EXPECT_DOUBLE_EQ(runs.samples[0].targetMm, 25.4);
  EXPECT_NEAR(runs.samples[0].deviationMm, 0.00025, 1e-15);
}

TEST(RunsCsv, AxisColumnAndFilter) {
  const std::string text =
      "axis,run,direction,target_mm,deviation_um\nX,1,+,0,1\nY,1,+,0,2\nx,2,+,0,3\n";
  const PositioningRuns x = parse(text, model::Axis::X);
  EXPECT_EQ(x.axis, model::Axis::X);
  EXPECT_EQ(x.samples.size(), 2u);
  try {
    parse(text);
    FAIL() << "two axes accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("several axes (X, Y): choose one with --axis"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(parse("run,direction,target_mm,deviation_um\n1,+,0,1\n", model::Axis::Z).axis,
            model::Axis::Z);
  EXPECT_FALSE(parse("run,direction,target_mm,deviation_um\n1,+,0,1\n").axis);
  EXPECT_NE(errorOf(text, model::Axis::Z).find("no readings of axis Z"), std::string::npos)
      << errorOf(text, model::Axis::Z);
}

TEST(RunsCsv, BadInputNamesFileLineAndColumn) {
  const auto message = [](const std::string& text) -> std::string {
    try {
      parse(text);
    } catch (const config::ConfigError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(message("run,direction,target,deviation_um\n"),
            "runs.csv: line 1, column target: a length column needs its unit in the header, e.g. "
            "\"target_mm\" (units: nm, um, mm, m, in)");
  EXPECT_EQ(message("run,direction,target_mm,deviation_um\n1,+,0,abc\n"),
            "runs.csv: line 2, column deviation_um: expected a finite number, got \"abc\"");
  EXPECT_NE(message("run,direction,target_mm,deviation_um\n1,sideways,0,1\n")
                .find("runs.csv: line 2, column direction: expected the approach direction"),
            std::string::npos);
  EXPECT_NE(message("run,direction,target_mm\n").find("has no deviation"), std::string::npos);
  EXPECT_NE(message("run,direction,target_mm,deviation_um\n1.5,+,0,1\n").find("run number"),
            std::string::npos);
  EXPECT_NE(message("run,direction,target_mm,deviation_um\n1,+\n").find("expected 4 fields"),
            std::string::npos);
  EXPECT_NE(message("run,direction,target_mm,deviation_furlong\n").find("has no deviation"),
            std::string::npos);
  EXPECT_EQ(message(""), "runs.csv: no header line (the file is empty)");
}

TEST(Iso230Refusals, FewerThanFiveRunsInADirection) {
  EXPECT_EQ(errorOf(table(5, 4, kTargets)),
            "runs.csv: 4 run(s) in the negative (↓) direction: ISO 230-2 needs at least 5 runs in "
            "each direction");
  EXPECT_NE(errorOf(table(5, 0, kTargets)).find("0 run(s) in the negative"), std::string::npos);
  EXPECT_NE(errorOf(table(3, 5, kTargets)).find("3 run(s) in the positive"), std::string::npos);
}

TEST(Iso230Refusals, FewerThanFiveTargets) {
  EXPECT_EQ(errorOf(table(5, 5, {0, 10, 25, 40})),
            "runs.csv: 4 target position(s): ISO 230-2 needs at least 5");
}

TEST(Iso230Refusals, UnequalTargets) {
  std::string text = table(5, 5, kTargets);
  // Drop run 3's reading at 39.5 going down.
  const std::string line = "3,-,39.5,1.3\n";
  ASSERT_NE(text.find(line), std::string::npos);
  text.erase(text.find(line), line.size());
  EXPECT_EQ(errorOf(text),
            "runs.csv: unequal targets: run 3 ↓ has no reading at target 39.5 mm (ISO 230-2 needs "
            "every run to visit the same target positions in both directions)");
  // A target only one run visits.
  EXPECT_NE(errorOf(table(5, 5, kTargets) + "2,+,50,0\n").find("has no reading at target 50 mm"),
            std::string::npos);
  // A second reading of a pass at the same target.
  EXPECT_NE(errorOf(table(5, 5, kTargets) + "2,+,62,0\n")
                .find("line 52: run 2 ↑ has a second reading at target 62 mm"),
            std::string::npos)
      << errorOf(table(5, 5, kTargets) + "2,+,62,0\n");
}

// What the file holds is shown escaped and shortened, in errors and in the list of unused columns
// (the list also goes into the JSON report, which must stay valid UTF-8).
TEST(RunsCsv, FileContentIsShownEscapedAndShort) {
  std::string huge(100000, 'u');
  try {
    parse("run,direction,target_mm,deviation_" + huge + "\n");
    ADD_FAILURE() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_LT(std::string(e.what()).size(), 600u) << e.what();
  }
  try {
    parse("run,direction,target_mm,deviation_um\n1,\x1b[5m\xc3,0,1\n");
    ADD_FAILURE() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("got \"\\x1b[5m\\xc3\""), std::string::npos) << e.what();
  }
  std::ostringstream csv;
  csv << "run,direction,target_mm,deviation_um";
  for (int i = 0; i < 12; ++i) csv << ",note\xff" << i;
  csv << '\n';
  for (int run = 1; run <= 5; ++run) {
    for (const char* direction : {"+", "-"}) {
      for (double target : {0.0, 97.0, 211.0, 305.0, 398.0}) {
        csv << run << ',' << direction << ',' << target << ',' << 0.1 * run << std::string(12, ',')
            << '\n';
      }
    }
  }
  const Iso230Result result = evaluateIso230_2(parse(csv.str()));
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0],
            "columns not used: \"note\\xff0\", \"note\\xff1\", \"note\\xff2\", \"note\\xff3\", "
            "\"note\\xff4\", \"note\\xff5\", \"note\\xff6\", \"note\\xff7\", \"note\\xff8\", "
            "\"note\\xff9\" and 2 more");
}

TEST(RunsCsv, AMillionColumnLineIsRefused) {
  std::string text = "run,direction,target_mm,deviation_um\n";
  for (int i = 0; i < 1000000; ++i) text += "1,";
  text += "1\n";
  try {
    parse(text);
    ADD_FAILURE() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_STREQ(e.what(), "runs.csv: line 2: longer than 1 MiB: not a line of this format");
  }
}

TEST(Iso230Warnings, EvenSpacingFewTargetsPerMetreUnequalRuns) {
  const Iso230Result even = evaluateIso230_2(parse(table(5, 5, {0, 100, 200, 300, 400})));
  ASSERT_EQ(even.warnings.size(), 1u);
  EXPECT_NE(even.warnings[0].find("evenly spaced (every interval 100 mm)"), std::string::npos);
  const Iso230Result sparse =
      evaluateIso230_2(parse(table(5, 6, {0, 230, 470, 690, 950, 1200, 1440})));
  ASSERT_EQ(sparse.warnings.size(), 2u);
  EXPECT_NE(sparse.warnings[0].find("5 runs ↑ but 6 runs ↓"), std::string::npos);
  EXPECT_NE(sparse.warnings[1].find("target positions per metre"), std::string::npos);
  const Iso230Result longAxis = evaluateIso230_2(
      parse(table(5, 5, {0, 240, 490, 760, 1010, 1230, 1500, 1740, 2010, 2250, 2500, 2760, 3000})));
  ASSERT_EQ(longAxis.warnings.size(), 1u);
  EXPECT_NE(longAxis.warnings[0].find("over 2000 mm differently"), std::string::npos);
}

}  // namespace
}  // namespace volcomp::metrology
