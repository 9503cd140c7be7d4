// Hanak, Zirn and Ruoff's device from the command line (`volcomp calibrate` with a "volcomp-planar2dof/1"
// device file, as a process): readings a,b,gx,gy; the paper's table 2 layout; the nine-parameter
// case names the two the data cannot separate; recovery of the paper's values within 2 sigma.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "planar_synthetic.hpp"
#include "run_cli.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
using volcomp::testing::CliRun;
using volcomp::testing::quoted;

// The files of one run.
struct CalibrateOptions {
  std::string templatePath;
  std::string measurementsPath;
  std::string outPath;
  std::string reportPath;
};

CliRun runCalibrate(const volcomp::testing::TempDir& dir, const CalibrateOptions& options) {
  std::string args = "calibrate " + quoted(options.templatePath) + " " +
                     quoted(options.measurementsPath) + " --out " + quoted(options.outPath);
  if (!options.reportPath.empty()) args += " --report " + quoted(options.reportPath);
  return volcomp::testing::runCli(dir, args);
}

// The paper's device file: nominal legs, reference point n = 1, the paper's 7 parameters and
// starting values (table 2; lengths mm, phi deg).
const char* kDevice = R"({
  "format": "volcomp-planar2dof/1", "name": "2DOF-System, FHTE",
  "legs_mm": [250, 250], "reference_point": 1,
  "free": ["eLa", "eLb", "ea", "eha", "phi", "exK", "eyK"],
  "start": {"eLa": 0.1, "eLb": 0.1, "ea": 1.0, "eha": 0.1, "phi": 0.057, "exK": 0.003, "eyK": 0.003}
})";

std::string readingsCsv(unsigned seed, double noiseMm) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "# a, b: scale readings of the two sliders; gx, gy: lattice grid plate, in um\n";
  csv << "a,b,gx_um,gy_um\n";
  for (const Planar2DofSample& s :
       testing::simulatePlanar(testing::paperOptimised(), noiseMm, seed)) {
    csv << s.aMm << ',' << s.bMm << ',' << s.lgpMm.x() * 1e3 << ',' << s.lgpMm.y() * 1e3 << '\n';
  }
  return csv.str();
}

json readJson(const std::string& file) {
  std::ifstream in(file);
  return json::parse(in);
}

TEST(Planar2DofCli, TableTwoLayoutAndTheFittedDevice) {
  volcomp::testing::TempDir dir;
  CalibrateOptions options;
  options.templatePath = dir.write("device.json", kDevice);
  options.measurementsPath = dir.write("readings.csv", readingsCsv(2026, 1.8e-3));
  options.outPath = (dir.path() / "fitted.json").string();
  options.reportPath = (dir.path() / "report.json").string();
  const CliRun out = runCalibrate(dir, options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  const std::string text = out.out;
  EXPECT_NE(text.find("Parameters     Starting values  Optimized values  Standard deviation s_i"),
            std::string::npos)
      << text;
  for (const char* row : {"eLa", "eLb", "ea", "eha", "phi", "exK", "eyK"}) {
    EXPECT_NE(text.find(std::string("\n") + row + " "), std::string::npos) << row << "\n" << text;
  }
  EXPECT_NE(text.find("0.057°"), std::string::npos) << text;  // phi's start, in degrees
  EXPECT_NE(text.find("3 µm"), std::string::npos) << text;    // exK's start, in um
  EXPECT_NE(text.find("correlations:"), std::string::npos) << text;
  EXPECT_NE(text.find("s_r (standard deviation of the position"), std::string::npos) << text;
  EXPECT_NE(text.find("mean deviation |dL|"), std::string::npos) << text;

  const json report = readJson(options.reportPath);
  EXPECT_EQ(report["kind"], "planar2dof");
  EXPECT_EQ(report["rank"], 7);
  ASSERT_EQ(report["parameters"].size(), 7u);
  EXPECT_EQ(report["parameters"][4]["name"], "phi");
  EXPECT_EQ(report["parameters"][4]["unit"], "deg");
  EXPECT_EQ(report["parameters"][5]["unit"], "um");
  EXPECT_EQ(report["correlation"].size(), 7u);
  // s_r: Hanak, Zirn and Ruoff found 2.0 um against a mean deviation of 2.3 um; with 1.8 um of reading
  // noise the propagated position sigma is of the same size, the mean deviation near
  // 1.8 sqrt(pi / 2) = 2.3 um.
  EXPECT_GT(report["s_r_mm"].get<double>(), 0.5e-3);
  EXPECT_LT(report["s_r_mm"].get<double>(), 3e-3);
  EXPECT_NEAR(report["mean_deviation_mm"]["after"].get<double>(), 2.3e-3, 0.8e-3);
  EXPECT_GT(report["mean_deviation_mm"]["before"].get<double>(), 20e-3);

  const json fitted = readJson(options.outPath);
  EXPECT_EQ(fitted["format"], "volcomp-planar2dof/1");
  EXPECT_NEAR(fitted["values"]["phi"].get<double>(), -0.184, 0.02);
  EXPECT_EQ(fitted["values"]["eb"], 0.0);  // fixed by the paper's choice
  EXPECT_TRUE(fitted["std"]["eLa"].is_number());
  EXPECT_FALSE(fitted["std"].contains("eb"));
}

TEST(Planar2DofCli, RecoversThePaperValuesWithinTwoSigma) {
  // As in planar2dof_test, over 20 data sets: >= 90 % of the 140 estimates within 2 sigma
  // (expected 95 %), none beyond 4 sigma; the report's values are in the table's units.
  volcomp::testing::TempDir dir;
  const Planar2DofParameters truth = testing::paperOptimised();
  const std::vector<std::pair<std::string, double>> expected{{"eLa", truth[eLa]},
                                                             {"eLb", truth[eLb]},
                                                             {"ea", truth[ea]},
                                                             {"eha", truth[eha]},
                                                             {"phi", truth[phi] / testing::kDeg},
                                                             {"exK", truth[exK] * 1e3},
                                                             {"eyK", truth[eyK] * 1e3}};
  int within = 0, total = 0;
  for (unsigned seed = 3000; seed < 3020; ++seed) {
    CalibrateOptions options;
    options.templatePath = dir.write("device.json", kDevice);
    options.measurementsPath = dir.write("readings.csv", readingsCsv(seed, 1.8e-3));
    options.outPath = (dir.path() / "fitted.json").string();
    options.reportPath = (dir.path() / "report.json").string();
    const CliRun out = runCalibrate(dir, options);
    ASSERT_EQ(out.status, 0) << out.out << out.err;
    const json report = readJson(options.reportPath);
    ASSERT_TRUE(report["converged"].get<bool>());
    for (std::size_t j = 0; j < expected.size(); ++j) {
      const json& p = report["parameters"][j];
      ASSERT_EQ(p["name"], expected[j].first);
      const double deviation = std::abs(p["value"].get<double>() - expected[j].second);
      const double sigma = p["std"].get<double>();
      EXPECT_LT(deviation, 4.0 * sigma) << p.dump();
      within += deviation < 2.0 * sigma ? 1 : 0;
      ++total;
    }
  }
  EXPECT_GE(static_cast<double>(within) / total, 0.9) << within << " of " << total;
}

TEST(Planar2DofCli, AllNineFreeNamesTheTwoThatCannotBeIdentified) {
  volcomp::testing::TempDir dir;
  json device = json::parse(kDevice);
  device["free"] = "all";
  CalibrateOptions options;
  options.templatePath = dir.write("device.json", device.dump());
  options.measurementsPath = dir.write("readings.csv", readingsCsv(7, 1e-3));
  options.outPath = (dir.path() / "fitted.json").string();
  options.reportPath = (dir.path() / "report.json").string();
  const CliRun out = runCalibrate(dir, options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  const json report = readJson(options.reportPath);
  EXPECT_EQ(report["rank"], 7);
  ASSERT_EQ(report["unidentifiable"].size(), 2u);
  EXPECT_EQ(report["unidentifiable"][0]["parameters"], json({"ea", "eb"}));
  EXPECT_EQ(report["unidentifiable"][1]["parameters"], json({"eha", "ehb"}));
  EXPECT_NE(out.out.find("ea and eb are not separable"), std::string::npos) << out.out;
  EXPECT_NE(out.out.find("not identifiable"), std::string::npos) << out.out;
  const json fitted = readJson(options.outPath);
  EXPECT_TRUE(fitted["std"]["eb"].is_null());
}

TEST(Planar2DofCli, BadDeviceFilesAndReadingsNameTheKeyOrLine) {
  volcomp::testing::TempDir dir;
  const auto error = [&](const std::string& device, const std::string& csv) {
    CalibrateOptions options;
    options.templatePath = dir.write("device.json", device);
    options.measurementsPath = dir.write("readings.csv", csv);
    options.outPath = (dir.path() / "fitted.json").string();
    // A ConfigError: exit status 2 and its one line on stderr.
    const CliRun run = runCalibrate(dir, options);
    EXPECT_EQ(run.status, 2) << run.out << run.err;
    EXPECT_EQ(run.errLines(), 1) << run.err;
    return run.status == 2 ? run.err : std::string();
  };
  json device = json::parse(kDevice);
  device["free"] = {"eLa", "psi"};
  EXPECT_NE(error(device.dump(), readingsCsv(1, 1e-3)).find("free[1]"), std::string::npos);
  device = json::parse(kDevice);
  device["reference_point"] = 99;
  EXPECT_NE(error(device.dump(), readingsCsv(1, 1e-3)).find("reference_point"), std::string::npos);
  EXPECT_NE(error(kDevice, "a,b,gx\n1,2,3\n").find("missing column \"gy\""), std::string::npos);
  EXPECT_NE(error(kDevice, "a,b,gx,gy\n1,2,3,x\n").find("line 2, column gy"), std::string::npos);
}

}  // namespace
}  // namespace volcomp::calibration
