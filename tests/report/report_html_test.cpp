// The report document without a browser: which sections it holds for which inputs, a table of
// contents that matches them, chart specs that are valid JSON and cannot end their script
// element, text escaped, numbers rounded like their uncertainty (seed 003's table 2), and the
// `volcomp report` verb as a process.

#include <gtest/gtest.h>

#include <regex>
#include <set>

#include "run_cli.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/report/assets.hpp"
#include "volcomp/report/report.hpp"

namespace volcomp::report {
namespace {

using nlohmann::json;
const std::string kExamples = VOLCOMP_EXAMPLES_DIR;
const std::string kData = VOLCOMP_REPORT_TEST_DATA;

ReportOptions options() {
  ReportOptions o;
  o.volcompVersion = "9.9.9";
  o.date = 1796126400;  // 2026-12-01 12:00 UTC
  o.mapResolution = 12;
  o.curveSamples = 41;
  return o;
}

ReportInputs modelOnly(const std::string& file = "vmc-xyfz-21.json") {
  ReportInputs inputs;
  inputs.model = config::loadModelFile(kExamples + "/" + file);
  inputs.files.push_back({"model", inputs.model.file, 1, ""});
  return inputs;
}

std::vector<std::string> matches(const std::string& html, const std::string& pattern) {
  std::vector<std::string> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(html.begin(), html.end(), re); it != std::sregex_iterator();
       ++it) {
    out.push_back((*it)[1]);
  }
  return out;
}

bool contains(const std::string& text, const std::string& fragment) {
  return text.find(fragment) != std::string::npos;
}

TEST(ReportDocument, ModelOnlyHasComponentsMapsAndInputs) {
  const RenderedReport r = renderReport(modelOnly(), options());
  std::vector<std::string> ids;
  for (const auto& [id, title] : r.sections) ids.push_back(id);
  EXPECT_EQ(ids, (std::vector<std::string>{"components", "maps", "inputs"}));
  // 3 axes x (translations + rotations) + 5 planes x (|E| + normal part).
  EXPECT_EQ(r.charts, 6 + 10);
  EXPECT_TRUE(contains(r.html, "<title>Machine accuracy report — VMC-850"));
  EXPECT_TRUE(contains(r.html, "volcomp 9.9.9"));
  EXPECT_TRUE(contains(r.html, "2026-12-01"));
  EXPECT_TRUE(contains(r.html, "no calibration report given"));
  // The table of contents links to every section and subsection, and nothing else.
  const std::vector<std::string> links = matches(r.html, "<a href=\"#([^\"]+)\"");
  std::set<std::string> anchors;
  for (const std::string& id : matches(r.html, " id=\"([^\"]+)\"")) anchors.insert(id);
  for (const std::string& link : links) EXPECT_TRUE(anchors.count(link)) << link;
  EXPECT_EQ(links.size(), 3U + 4U + 5U);  // sections; axes X Y Z and the table; 5 planes
}

TEST(ReportDocument, EveryChartSpecIsJsonAndEveryChartHasOne) {
  const RenderedReport r = renderReport(modelOnly("gantry-fxyz-grid.json"), options());
  const std::vector<std::string> charts = matches(r.html, "class=\"chart\" id=\"([^\"]+)\"");
  const std::vector<std::string> specIds =
      matches(r.html, "<script type=\"application/json\" id=\"spec-([^\"]+)\">");
  EXPECT_EQ(charts, specIds);
  EXPECT_EQ(static_cast<int>(charts.size()), r.charts);
  EXPECT_TRUE(contains(r.html, "grid-1"));  // the gantry's beam-sag grid
  const std::regex spec("<script type=\"application/json\" id=\"spec-[^\"]+\">([^<]*)</script>");
  int parsed = 0;
  for (auto it = std::sregex_iterator(r.html.begin(), r.html.end(), spec);
       it != std::sregex_iterator(); ++it) {
    const json document = json::parse((*it)[1].str());
    EXPECT_TRUE(document.contains("marks"));
    EXPECT_TRUE(document.contains("axes") || document.contains("marks"));
    ++parsed;
  }
  EXPECT_EQ(parsed, r.charts);
  // Vega, the drawing script and the stylesheet are in the file.
  EXPECT_TRUE(contains(r.html, vegaRuntime()));
  EXPECT_TRUE(contains(r.html, reportScript()));
  EXPECT_TRUE(contains(r.html, "BSD-3-Clause"));
  EXPECT_FALSE(contains(r.html, "src=\"http"));
  EXPECT_FALSE(contains(r.html, "href=\"http"));
}

TEST(ReportDocument, TextIsEscapedAndSpecsCannotEndTheirScript) {
  ReportOptions o = options();
  o.machine = "VMC </script><b>&";
  const RenderedReport r = renderReport(modelOnly(), o);
  EXPECT_TRUE(contains(r.html, "VMC &lt;/script&gt;&lt;b&gt;&amp;"));
  EXPECT_FALSE(contains(r.html, "VMC </script>"));
}

TEST(ReportDocument, AllInputsGiveAllSectionsInOrder) {
  ReportInputs inputs = modelOnly();
  Notes notes;
  inputs.iso.push_back(loadIsoAxis(kData + "/iso230-2-x.json", notes));
  inputs.run = loadRunSummary(kData + "/run-summary.json", notes);
  inputs.writes = loadRecordedWrites(kData + "/run-writes.csv");
  inputs.calibration = readCalibrationReport(
      json::parse(R"({"format": "volcomp-calibration-report/1", "points": 3, "rank": 1,
        "parameter_count": 1, "parameters": [{"name": "eLa", "unit": "mm", "start": 0.1,
        "value": 0.30, "std": 0.18, "identifiable": true}],
        "correlation": [[1]], "residuals": {"before": {"rms_mm": 0.01}, "after": {"rms_mm": 0.001}}})"),
      "cal.json", notes);
  const RenderedReport r = renderReport(inputs, options());
  std::vector<std::string> ids;
  for (const auto& [id, title] : r.sections) ids.push_back(id);
  EXPECT_EQ(ids, (std::vector<std::string>{"components", "maps", "calibration", "iso230-2", "run",
                                           "inputs"}));
  // Summary: the manager's sentences and cards for each input.
  EXPECT_TRUE(contains(r.html, "predicts a tool-tip error of up to"));
  EXPECT_TRUE(contains(r.html, "live compensation reduced the RMS tool-tip error"));
  EXPECT_TRUE(contains(r.html, "ISO 230-2 positioning of X: accuracy A ="));
  EXPECT_TRUE(contains(r.html, "Calibration residual"));
  // Without the measurements, no residuals per point, and the appendix says so.
  EXPECT_TRUE(contains(r.html, "calibration residuals per point: the measurement file"));
  // Seed 003's table 2 row: 0.30 mm with 0.18 mm.
  EXPECT_TRUE(contains(r.html, "0.30&#8239;mm</td><td class=\"num\">0.18&#8239;mm"));
}

TEST(ReportDocument, ADhChainGetsAReportWithoutMaps) {
  const RenderedReport r = renderReport(modelOnly("seed000-cartesian-table.json"), options());
  ASSERT_EQ(r.sections.size(), 2U);
  EXPECT_EQ(r.charts, 0);
  EXPECT_TRUE(contains(r.html, "Denavit-Hartenberg chain"));
  // Seed 000's perpendicularity deviation of link 2, alpha_e1 = -0.00013544 deg.
  EXPECT_TRUE(contains(r.html, "−0.0001354"));
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
  EXPECT_EQ(x.axis, "X");
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
