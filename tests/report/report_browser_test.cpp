// The report as a person sees it: written by `volcomp report` from a calibration done the way
// the end-to-end calibration test does it (the simulator's true VMC measured with noise,
// `volcomp calibrate` with the example template), `volcomp iso230-2` of the example laser test
// of X and a recorded demo run, then opened from disk in headless Chromium (Debian's `chromium`,
// DevTools protocol on a pipe). Checks: no console error or warning, no network request, every
// chart drew marks, a screenshot of each section kept in the build directory, and plotted values
// equal to the model's.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "headless_chromium.hpp"
#include "subprocess.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::report {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Json = nlohmann::json;

const std::string kCli = VOLCOMP_CLI;
const std::string kBrowser = VOLCOMP_CHROMIUM;
const fs::path kExamples = VOLCOMP_EXAMPLES_DIR;
const fs::path kData = VOLCOMP_REPORT_TEST_DATA;
const fs::path kArtefacts = VOLCOMP_REPORT_ARTEFACTS;

constexpr double kNoiseMm = 0.0005;

std::string runCli(const std::vector<std::string>& args, const fs::path& errFile) {
  std::vector<std::string> argv{kCli};
  argv.insert(argv.end(), args.begin(), args.end());
  testutil::Subprocess cli(argv, errFile.string(), {"SOURCE_DATE_EPOCH=1796126400"});
  std::string out;
  while (const auto line = cli.readLine(120s)) out += *line + '\n';
  const int status = cli.waitExit(10s);
  if (status != 0) {
    throw std::runtime_error("volcomp " + args.front() + " failed (" + std::to_string(status) +
                             "): " + testutil::readTextFile(errFile.string()));
  }
  return out;
}

// The true machine measured on a grid (at the template's X nodes, every 50 mm in Y, 9 Z levels)
// with four tool offsets, noise added: the calibration's input, as
// tests/e2e/calibration_e2e_test.cpp makes it (half as dense in X here).
fs::path measure(const fs::path& dir) {
  {
    std::ofstream grid(dir / "grid.csv");
    grid << "x,y,z\n";
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j)
        for (int k = 0; k <= 8; ++k)
          grid << 85 * i << ',' << 50 * j << ',' << -500 + 62.5 * k << '\n';
  }
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, kNoiseMm);
  std::ofstream out(dir / "measurements.csv");
  out.precision(9);
  out << "x,y,z,ex,ey,ez,tx,ty,tz\n";
  const std::vector<std::string> tools{"0,0,120", "0,0,220", "100,0,120", "0,100,120"};
  for (std::size_t t = 0; t < tools.size(); ++t) {
    const fs::path exact = dir / ("exact" + std::to_string(t) + ".csv");
    runCli({"eval", (kExamples / "vmc-xyfz-21-true.json").string(), "--points",
            (dir / "grid.csv").string(), "--out", exact.string(), "--tool", tools[t]},
           dir / "eval.err");
    std::ifstream in(exact);
    std::string line;
    std::getline(in, line);
    while (std::getline(in, line)) {
      std::stringstream fields(line);
      std::vector<double> f;
      for (std::string s; std::getline(fields, s, ',');) f.push_back(std::stod(s));
      out << f[0] << ',' << f[1] << ',' << f[2];
      for (std::size_t k = 3; k < 6; ++k) out << ',' << f[k] + noise(rng);
      out << ',' << tools[t] << '\n';
    }
  }
  return dir / "measurements.csv";
}

struct Rect {
  std::string id;
  double x, y, width, height;
};

class ReportInBrowser : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(kArtefacts);
    fs::create_directories(kArtefacts / "work");
    const fs::path work = kArtefacts / "work";
    const fs::path measurements = measure(work);
    runCli({"calibrate", (kExamples / "vmc-xyfz-21-template.json").string(), measurements.string(),
            "--out", (work / "calibrated.json").string(), "--report",
            (work / "calibration.json").string()},
           work / "calibrate.err");
    runCli({"iso230-2", (kExamples / "iso230-2-x-runs.csv").string(), "--json",
            (work / "iso230-2-x.json").string()},
           work / "iso230-2.err");
    reportPath_ = kArtefacts / "report.html";
    cliOutput_ =
        runCli({"report", (work / "calibrated.json").string(), "--calibration",
                (work / "calibration.json").string(), "--iso230-2",
                (work / "iso230-2-x.json").string(), "--run", (kData / "run-summary.json").string(),
                "--writes", (kData / "run-writes.csv").string(), "--machine",
                "VMC-850 (example data)", "--out", reportPath_.string()},
               work / "report.err");
    calibrated_ = std::make_unique<model::MachineModel>(std::get<model::MachineModelSpec>(
        config::loadModelFile((work / "calibrated.json").string()).spec));

    fs::create_directories(kArtefacts / "profile");
    browser_ = std::make_unique<testutil::HeadlessChromium>(
        kBrowser, (kArtefacts / "profile").string(), (kArtefacts / "chromium.log").string());
    for (const char* domain : {"Runtime.enable", "Log.enable", "Network.enable", "Page.enable"}) {
      browser_->call(domain);
    }
    browser_->call("Emulation.setDeviceMetricsOverride",
                   {{"width", 1200}, {"height", 900}, {"deviceScaleFactor", 1}, {"mobile", false}});
    const std::size_t from = browser_->events().size();
    const auto start = std::chrono::steady_clock::now();
    browser_->call("Page.navigate", {{"url", "file://" + fs::absolute(reportPath_).string()}});
    browser_->awaitEvent("Page.loadEventFired", from, 60s);
    drawn_ = browser_->evaluate(
        "volcompReport.ready.then(r => ({charts: r.charts, errors: r.errors, "
        "renderMs: r.renderMs}))",
        true);
    wallMs_ =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

  static void TearDownTestSuite() {
    browser_.reset();
    calibrated_.reset();
    fs::remove_all(kArtefacts / "profile");
  }

  static inline fs::path reportPath_;
  static inline std::string cliOutput_;
  static inline std::unique_ptr<testutil::HeadlessChromium> browser_;
  static inline std::unique_ptr<model::MachineModel> calibrated_;
  static inline Json drawn_;
  static inline double wallMs_ = 0.0;
};

TEST_F(ReportInBrowser, OpensOfflineWithoutConsoleErrors) {
  ASSERT_TRUE(drawn_.is_object()) << drawn_.dump();
  EXPECT_TRUE(drawn_["errors"].empty()) << drawn_["errors"].dump();
  int checked = 0;
  for (const Json& event : browser_->events()) {
    const std::string method = event["method"];
    const Json& params = event["params"];
    if (method == "Runtime.consoleAPICalled") {
      const std::string type = params["type"];
      EXPECT_TRUE(type != "error" && type != "warning" && type != "assert")
          << "console." << type << ": " << params["args"].dump();
    } else if (method == "Runtime.exceptionThrown") {
      ADD_FAILURE() << "exception: " << params["exceptionDetails"].dump();
    } else if (method == "Log.entryAdded") {
      EXPECT_NE(params["entry"]["level"], "error") << params["entry"].dump();
    } else if (method == "Network.requestWillBeSent") {
      // The report itself is the only thing loaded: no script, font or data from elsewhere.
      const std::string url = params["request"]["url"];
      EXPECT_EQ(url.rfind("file://", 0), 0U) << "request to " << url;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 1) << "exactly one request: the report file";
  const auto bytes = fs::file_size(reportPath_);
  std::cout << "report: " << bytes / 1024 << " KiB, " << drawn_["charts"].size()
            << " charts drawn; ready " << drawn_["renderMs"].get<double>()
            << " ms after navigation start (" << wallMs_ << " ms wall, navigate to ready)\n"
            << cliOutput_;
  RecordProperty("report_bytes", std::to_string(bytes));
  RecordProperty("render_ms", std::to_string(drawn_["renderMs"].get<double>()));
}

TEST_F(ReportInBrowser, EveryChartHasMarks) {
  // What report.js counted in Vega's scene graph, and independently the SVG elements of the
  // charts' own marks (role "mark", not axes or legends) in the document.
  const Json dom = browser_->evaluate(
      "Array.from(document.querySelectorAll('.chart')).map(c => ({id: c.id, "
      "svg: c.querySelectorAll('svg').length, "
      "marks: Array.from(c.querySelectorAll('g.role-mark:not(.mark-group)'))"
      ".reduce((n, g) => n + g.children.length, 0)}))");
  ASSERT_GE(dom.size(), 20U) << dom.dump();
  ASSERT_EQ(drawn_["charts"].size(), dom.size());
  for (const Json& chart : drawn_["charts"]) {
    EXPECT_GT(chart["marks"].get<int>(), 0) << chart["id"];
  }
  for (const Json& chart : dom) {
    EXPECT_EQ(chart["svg"], 1) << chart["id"];
    EXPECT_GT(chart["marks"].get<int>(), 0) << chart["id"] << " drew no marks";
  }
  // Every kind of section has its charts.
  for (const char* id :
       {"components-X-translations", "components-X-rotations", "calibration-residuals",
        "calibration-histogram-before", "calibration-histogram-after", "calibration-correlation",
        "iso-X-chart", "run-rms", "run-offsets"}) {
    bool found = false;
    for (const Json& chart : dom) found = found || chart["id"] == id;
    EXPECT_TRUE(found) << id;
  }
}

TEST_F(ReportInBrowser, ScreenshotOfEverySection) {
  const Json rects = browser_->evaluate(
      "Array.from(document.querySelectorAll('section')).map(s => { const r = "
      "s.getBoundingClientRect(); return {id: s.id, x: r.left + scrollX, y: r.top + scrollY, "
      "width: r.width, height: r.height}; })");
  std::vector<std::string> ids;
  for (const Json& r : rects) ids.push_back(r["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"summary", "components", "maps", "calibration",
                                           "iso230-2", "run", "inputs"}));
  for (const Json& r : rects) {
    // The section with a margin of 16 px, at most 6000 px high (Chromium's limit is far above).
    const Json clip{{"x", std::max(0.0, r["x"].get<double>() - 16)},
                    {"y", std::max(0.0, r["y"].get<double>() - 16)},
                    {"width", r["width"].get<double>() + 32},
                    {"height", std::min(6000.0, r["height"].get<double>() + 32)},
                    {"scale", 1}};
    const Json shot =
        browser_->call("Page.captureScreenshot",
                       {{"format", "png"}, {"clip", clip}, {"captureBeyondViewport", true}});
    const std::string png = testutil::decodeBase64(shot["data"]);
    ASSERT_GT(png.size(), 2000U) << r["id"];
    EXPECT_EQ(png.substr(1, 3), "PNG");
    const fs::path file = kArtefacts / ("section-" + r["id"].get<std::string>() + ".png");
    std::ofstream(file, std::ios::binary) << png;
    std::cout << "screenshot " << file.string() << " (" << png.size() / 1024 << " KiB)\n";
  }
}

// Printed (A4, as the stylesheet asks): every section starts a page of its own, so the PDF has
// at least one page per section; kept beside the screenshots.
TEST_F(ReportInBrowser, PrintsOnA4WithASectionPerPage) {
  const Json pdf = browser_->call("Page.printToPDF",
                                  {{"printBackground", true}, {"preferCSSPageSize", true}}, 120s);
  const std::string bytes = testutil::decodeBase64(pdf["data"]);
  ASSERT_EQ(bytes.substr(0, 5), "%PDF-");
  std::size_t pages = 0;
  for (std::size_t at = bytes.find("/Type /Page"); at != std::string::npos;
       at = bytes.find("/Type /Page", at + 1)) {
    if (bytes.compare(at, 12, "/Type /Pages") != 0) ++pages;
  }
  EXPECT_GE(pages, 7U);
  std::ofstream(kArtefacts / "report.pdf", std::ios::binary) << bytes;
  std::cout << "printed: " << pages << " A4 pages, " << bytes.size() / 1024 << " KiB\n";
}

// Reads a chart back as a reader would: the vertices of the drawn SVG path of one curve, mapped
// through the chart's scales, must be the model's values; and the y axis' tick labels must sit
// where the scale puts their values (so that the axis tells the truth about the curve).
TEST_F(ReportInBrowser, PlottedComponentValuesAreTheModels) {
  const Json curves = browser_->evaluate(R"js((() => {
    const id = 'components-X-translations';
    const view = volcompReport.views[id];
    const x = view.scale('x'), y = view.scale('y');
    const labels = [];
    (function walk(node) {
      (node.items || []).forEach(item => {
        if (node.marktype === 'line' && node.name === 'curve' && item.datum) {
          if (!labels.includes(item.datum.c)) labels.push(item.datum.c);
        }
        (item.items || []).forEach(walk);
      });
    })(view.scenegraph().root);
    const paths = Array.from(document.querySelectorAll('#' + id + ' g.mark-line.curve path'));
    const curves = paths.map((path, i) => ({
      label: labels[i],
      points: path.getAttribute('d').replace(/^M/, '').split('L').map(pair => {
        const [px, py] = pair.split(',').map(Number);
        return [x.invert(px), y.invert(py)];
      })
    }));
    // The y axis' labels (right-aligned, left of the plot): where each one is drawn and where
    // the scale puts the value it reads.
    const ticks = Array.from(document.querySelectorAll('#' + id + ' g.role-axis-label text'))
      .filter(t => t.getAttribute('text-anchor') === 'end')
      .map(t => {
        const value = Number(t.textContent.replace('\u2212', '-').replace(/,/g, ''));
        const drawnY = Number(/translate\([^,]+,([^)]+)\)/.exec(t.getAttribute('transform'))[1]);
        return {text: t.textContent, drawnY, scaledY: y(value)};
      });
    return {curves, ticks};
  })())js");
  const model::MachineModel& model = *calibrated_;
  // The curves the chart must hold: X's non-zero translations, two for a bidirectional table.
  std::vector<std::string> expected;
  for (int kind = 0; kind < 3; ++kind) {
    const int index = model::motionIndex(model::Axis::X, static_cast<model::MotionKind>(kind));
    if (model.motion(index).isZero()) continue;
    const std::string name = model::motionName(index);
    if (model.motion(index).isBidirectional()) {
      expected.push_back(name + " ↑");
      expected.push_back(name + " ↓");
    } else {
      expected.push_back(name);
    }
  }
  ASSERT_EQ(curves["curves"].size(), expected.size()) << curves.dump();
  int compared = 0;
  for (std::size_t c = 0; c < expected.size(); ++c) {
    const Json& curve = curves["curves"][c];
    const std::string label = curve["label"];
    EXPECT_EQ(label, expected[c]);
    const std::string name = label.substr(0, 3);
    int index = -1;
    for (int i = 0; i < 18; ++i) {
      if (model::motionName(i) == name) index = i;
    }
    ASSERT_GE(index, 0) << label;
    const model::Direction direction = label.ends_with("↑")   ? model::Direction::Positive
                                       : label.ends_with("↓") ? model::Direction::Negative
                                                              : model::Direction::Unknown;
    ASSERT_EQ(curve["points"].size(), 161U) << label;
    for (const Json& point : curve["points"]) {
      const double q = point[0].get<double>(), plottedUm = point[1].get<double>();
      const double modelUm = model.motion(index).value(q, direction) * 1000.0;
      // SVG coordinates carry 3 decimals of a pixel: about 1e-4 µm here.
      ASSERT_NEAR(plottedUm, modelUm, 2e-3) << label << " at X = " << q << " mm";
      ++compared;
    }
  }
  EXPECT_EQ(compared, static_cast<int>(161 * expected.size()));
  // Each label sits where the scale puts its value, up to the one shift that centres text on
  // its line (the same for every label, a few px for 11 px text).
  ASSERT_GE(curves["ticks"].size(), 3U) << curves.dump();
  const double shift =
      curves["ticks"][0]["drawnY"].get<double>() - curves["ticks"][0]["scaledY"].get<double>();
  EXPECT_LT(std::abs(shift), 5.0);
  for (const Json& tick : curves["ticks"]) {
    EXPECT_NEAR(tick["drawnY"].get<double>() - tick["scaledY"].get<double>(), shift, 0.5)
        << "y axis label " << tick["text"];
  }
}

TEST_F(ReportInBrowser, MapCellsAreTheModelsError) {
  const Json cells = browser_->evaluate(R"js((() => {
    const id = Object.keys(volcompReport.views).find(k => k.startsWith('map-XY') &&
                                                          k.endsWith('-magnitude'));
    const view = volcompReport.views[id];
    const out = [];
    (function walk(node) {
      (node.items || []).forEach(item => {
        if (node.marktype === 'rect' && node.name === 'cell-rects') out.push(item.datum);
        (item.items || []).forEach(walk);
      });
    })(view.scenegraph().root);
    return {id, cells: out};
  })())js");
  const std::string id = cells["id"];
  ASSERT_FALSE(cells["cells"].empty()) << id;
  // The first XY map is the top of the Z travel.
  const double z = calibrated_->spec().travelMm[2]->at(1);
  model::Workspace ws;
  for (const Json& cell : cells["cells"]) {
    const Eigen::Vector3d q(cell["a"].get<double>(), cell["b"].get<double>(), z);
    const model::PointError e = model::evaluate(*calibrated_, ws, q);
    ASSERT_NEAR(cell["m"].get<double>(), e.errorMm.norm() * 1000.0, 1e-3)
        << id << " at " << q.transpose();
    ASSERT_NEAR(cell["w"].get<double>(), e.errorMm.z() * 1000.0, 1e-3) << id;
  }
}

}  // namespace
}  // namespace volcomp::report
