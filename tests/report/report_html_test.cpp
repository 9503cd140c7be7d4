// The report document without a browser: which sections it holds for which inputs, a table of
// contents that matches them, chart specs that are valid JSON and cannot end their script
// element, text escaped, numbers rounded like their uncertainty (as Hanak, Zirn and Ruoff's
// table 2 rounds them). The `volcomp report` verb as a process: report_verb_test.cpp.

#include <gtest/gtest.h>

#include <regex>
#include <set>

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
  // Hanak, Zirn and Ruoff's table 2 row: 0.30 mm with 0.18 mm.
  EXPECT_TRUE(contains(r.html, "0.30&#8239;mm</td><td class=\"num\">0.18&#8239;mm"));
}

TEST(ReportDocument, ADhChainGetsAReportWithoutMaps) {
  const RenderedReport r = renderReport(modelOnly("cartesian-table-dh.json"), options());
  ASSERT_EQ(r.sections.size(), 2U);
  EXPECT_EQ(r.charts, 0);
  EXPECT_TRUE(contains(r.html, "Denavit-Hartenberg chain"));
  // Bulla Ramos et al.'s perpendicularity deviation of link 2, alpha_e1 = -0.00013544 deg.
  EXPECT_TRUE(contains(r.html, "−0.0001354"));
}

}  // namespace
}  // namespace volcomp::report
