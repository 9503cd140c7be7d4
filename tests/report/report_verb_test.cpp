// The `volcomp report` verb as a process: the file it writes, what it reads from the other verbs,
// and one line with status 2 for each bad input.

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {
namespace {

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;
const std::string kData = VOLCOMP_REPORT_TEST_DATA;

bool contains(const std::string& text, const std::string& fragment) {
  return text.find(fragment) != std::string::npos;
}

TEST(ReportVerb, WritesTheFileAndSaysWhere) {
  testing::TempDir dir;
  const std::string out = (dir.path() / "r.html").string();
  const testing::CliRun run =
      testing::runCli(dir, "report " + testing::quoted(kExamples + "/vmc-xyfz-21.json") +
                               " --run " + testing::quoted(kData + "/run-summary.json") +
                               " --map-cells 8 --out " + testing::quoted(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(contains(run.out, "report written to " + out));
  EXPECT_TRUE(contains(run.out, "Compensation run"));
  EXPECT_TRUE(contains(testing::readFile(out), "</html>"));
}

// The reader against the writer: `volcomp iso230-2 --json` of the example laser test.
TEST(ReportVerb, ReadsWhatIso230TwoWrites) {
  testing::TempDir dir;
  const std::string jsonPath = (dir.path() / "x.json").string();
  const testing::CliRun iso =
      testing::runCli(dir, "iso230-2 " + testing::quoted(kExamples + "/iso230-2-x-runs.csv") +
                               " --json " + testing::quoted(jsonPath));
  ASSERT_EQ(iso.status, 0) << iso.err;
  Notes notes;
  const IsoAxis x = loadIsoAxis(jsonPath, notes);
  EXPECT_TRUE(notes.empty()) << notes.front();
  EXPECT_EQ(x.axis, model::Axis::X);
  EXPECT_EQ(x.runsUp, 5);
  EXPECT_EQ(x.runsDown, 5);
  EXPECT_EQ(x.targets.size(), 9U);
  ASSERT_EQ(x.figures.size(), 12U);
  const nlohmann::json document = readJsonFile(jsonPath);
  EXPECT_DOUBLE_EQ(x.figures.back().valueUm,
                   document["axis_figures"]["accuracy_bidirectional"].get<double>() * 1e3);
  for (const IsoTarget& t : x.targets) {
    EXPECT_EQ(t.runsUp.size(), 5U);
    EXPECT_NEAR(*t.mean, 0.5 * (*t.meanUp + *t.meanDown), 1e-9);
  }
}

TEST(ReportVerb, BadInputsGiveOneLineAndStatusTwo) {
  testing::TempDir dir;
  const std::string model = testing::quoted(kExamples + "/vmc-xyfz-21.json");
  const std::string bad = dir.write("bad.json", "{\"format\": \"volcomp-model/1\"}");
  struct Case {
    std::string args, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"report " + testing::quoted(dir.path() / "none.json"), "none.json"},
           {"report " + model + " --calibration " + testing::quoted(bad), "bad.json: format"},
           {"report " + model + " --run " + testing::quoted(bad), "bad.json"},
           {"report " + model + " --measurements x.csv", "--measurements and --template"},
           {"report " + model + " --z-levels 1,a", "--z-levels"}}) {
    const testing::CliRun run =
        testing::runCli(dir, c.args + " --out " + testing::quoted(dir.path() / "o.html"));
    EXPECT_EQ(run.status, 2) << c.args;
    EXPECT_EQ(run.errLines(), 1) << run.err;
    EXPECT_TRUE(contains(run.err, c.expected)) << run.err;
  }
}

}  // namespace
}  // namespace volcomp::report
