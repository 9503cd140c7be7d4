// runCalibrate (the `volcomp calibrate` verb) on files: output model, report JSON, summary.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "synthetic.hpp"
#include "volcomp/calibration/run_calibrate.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

class RunCalibrate : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device device;
    directory_ = fs::temp_directory_path() /
                 ("volcomp-calibrate-" + std::to_string(device()) + "-" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string write(const std::string& name, const std::string& text) {
    const fs::path path = directory_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  std::string path(const std::string& name) const { return (directory_ / name).string(); }

  // Measurements of the FXYZ truth below with two tool lengths, as CSV text.
  static std::string measurementCsv() {
    const json truth{{"format", "volcomp-model/1"},
                     {"topology", "FXYZ"},
                     {"tool", {0, 0, 100}},
                     {"error_units", {{"length", "um"}, {"angle", "urad"}}},
                     {"components",
                      {{"EXX", {{"polynomial", {3.0, 0.012}}}},
                       {"EBX", 25.0},
                       {"EXZ", {{"polynomial", {0.0, -0.02}}}}}}};
    testing::SyntheticOptions options;
    options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
    options.noiseMm = 5e-4;
    const MeasurementSet set = testing::simulate(testing::machineSpec(truth), options);
    std::ostringstream csv;
    csv.precision(17);
    csv << "x,y,z,tx,ty,tz,ex,ey,ez\n";
    for (const Measurement& m : set.points) {
      csv << m.qMm.x() << ',' << m.qMm.y() << ',' << m.qMm.z() << ',' << m.toolMm.x() << ','
          << m.toolMm.y() << ',' << m.toolMm.z() << ',' << m.errorMm.x() << ',' << m.errorMm.y()
          << ',' << m.errorMm.z() << '\n';
    }
    return csv.str();
  }

  static std::string templateText(bool withStraightness) {
    json t{{"format", "volcomp-model/1"},
           {"name", "test machine"},
           {"topology", "FXYZ"},
           {"tool", {0, 0, 100}},
           {"error_units", {{"length", "um"}, {"angle", "urad"}}},
           {"components",
            {{"EXX", {{"identify", {{"basis", "polynomial"}, {"degree", 1}}}}},
             {"EBX", {{"identify", "constant"}}},
             {"EXZ", {{"identify", {{"basis", "polynomial"}, {"degree", 1}, {"zero_at", 0}}}}}}}};
    if (withStraightness) {
      // EXY's constant duplicates EXX c0: a combination the report must name.
      t["components"]["EXY"] = {{"identify", {{"basis", "polynomial"}, {"degree", 0}}}};
    }
    return t.dump();
  }

  fs::path directory_;
};

TEST_F(RunCalibrate, WritesALoadableModelAReportAndASummary) {
  CalibrateOptions options;
  options.templatePath = write("template.json", templateText(false));
  options.measurementsPath = write("points.csv", measurementCsv());
  options.outPath = path("model.json");
  options.reportPath = path("report.json");
  std::ostringstream out;
  EXPECT_EQ(runCalibrate(options, out), 0);

  // The output is an ordinary model file (no identify blocks), in the template's units.
  const config::ModelDocument model = config::loadModelFile(options.outPath);
  EXPECT_TRUE(model.identify.empty());
  EXPECT_EQ(model.units.length, "um");
  const auto& spec = std::get<model::MachineModelSpec>(model.spec);
  EXPECT_EQ(spec.name, "test machine");
  const double ebx = std::get<double>(spec.motion[4]);
  EXPECT_NEAR(ebx, 25e-6, 1e-6);

  std::ifstream reportFile(options.reportPath);
  const json report = json::parse(reportFile);
  EXPECT_EQ(report["format"], "volcomp-calibration-report/1");
  EXPECT_EQ(report["rank"], 4);
  EXPECT_EQ(report["parameters"].size(), 4u);
  EXPECT_EQ(report["parameters"][0]["name"], "EBX");
  EXPECT_EQ(report["parameters"][0]["unit"], "urad");
  EXPECT_NEAR(report["parameters"][0]["value"].get<double>(), 25.0,
              4.0 * report["parameters"][0]["std"].get<double>());
  EXPECT_EQ(report["correlation"].size(), 4u);
  EXPECT_GT(report["residuals"]["before"]["rms_mm"].get<double>(),
            report["residuals"]["after"]["rms_mm"].get<double>());
  EXPECT_TRUE(report["residuals"]["before"].contains("max_line"));
  EXPECT_TRUE(report["unidentifiable"].empty());
  EXPECT_NEAR(report["s0_mm"].get<double>(), 5e-4, 1e-4);

  const std::string summary = out.str();
  EXPECT_NE(summary.find("EXZ c1"), std::string::npos) << summary;
  EXPECT_NE(summary.find("rank 4 of 4"), std::string::npos) << summary;
  EXPECT_NE(summary.find("residual |e| before"), std::string::npos) << summary;
  EXPECT_NE(summary.find("iteration 1"), std::string::npos) << summary;  // progress
}

TEST_F(RunCalibrate, NamesWhatTheDataCannotSeparate) {
  CalibrateOptions options;
  options.templatePath = write("template.json", templateText(true));
  options.measurementsPath = write("points.csv", measurementCsv());
  options.outPath = path("model.json");
  options.reportPath = path("report.json");
  std::ostringstream out;
  EXPECT_EQ(runCalibrate(options, out), 0);
  std::ifstream reportFile(options.reportPath);
  const json report = json::parse(reportFile);
  EXPECT_EQ(report["rank"], 4);
  ASSERT_EQ(report["unidentifiable"].size(), 1u);
  const json& names = report["unidentifiable"][0]["parameters"];
  EXPECT_EQ(names, (json{"EXX c0", "EXY c0"})) << report["unidentifiable"].dump();
  EXPECT_NE(out.str().find("EXX c0 and EXY c0 are not separable"), std::string::npos) << out.str();
}

TEST_F(RunCalibrate, LevenbergMarquardtWithRobustLossResistsAnOutlier) {
  std::string csv = measurementCsv();
  // Spoil one measurement by 0.5 mm in x (a mis-read point).
  const std::size_t secondLine = csv.find('\n') + 1;
  const std::size_t end = csv.find('\n', secondLine);
  std::string row = csv.substr(secondLine, end - secondLine);
  const std::size_t lastComma = row.rfind(',');
  const std::size_t exComma = row.rfind(',', row.rfind(',', lastComma - 1) - 1);
  row = row.substr(0, exComma + 1) + "0.5" + row.substr(row.find(',', exComma + 1));
  csv.replace(secondLine, end - secondLine, row);
  CalibrateOptions options;
  options.templatePath = write("template.json", templateText(false));
  options.measurementsPath = write("points.csv", csv);
  options.outPath = path("model.json");
  options.reportPath = path("report.json");
  options.loss = "cauchy";
  options.lossScaleMm = 0.002;
  std::ostringstream out;
  EXPECT_EQ(runCalibrate(options, out), 0);
  std::ifstream reportFile(options.reportPath);
  const json report = json::parse(reportFile);
  EXPECT_EQ(report["method"], "levenberg-marquardt");
  EXPECT_EQ(report["residuals"]["after"]["max_line"], 2);  // the outlier stands out
  // EBX (25 urad) is still recovered to well under a micro-radian despite the outlier.
  EXPECT_NEAR(report["parameters"][0]["value"].get<double>(), 25.0, 0.5);
}

TEST_F(RunCalibrate, TemplateWithoutIdentifyBlocksIsRejected) {
  CalibrateOptions options;
  options.templatePath =
      write("template.json", R"({"format": "volcomp-model/1", "topology": "FXYZ"})");
  options.measurementsPath = write("points.csv", measurementCsv());
  options.outPath = path("model.json");
  std::ostringstream out;
  try {
    runCalibrate(options, out);
    FAIL() << "expected a ConfigError";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to identify"), std::string::npos);
    EXPECT_EQ(e.file(), options.templatePath);
  }
  EXPECT_FALSE(fs::exists(options.outPath));
}

TEST_F(RunCalibrate, RobustLossWithTheLinearMethodIsAnOptionError) {
  CalibrateOptions options;
  options.templatePath = write("template.json", templateText(false));
  options.measurementsPath = write("points.csv", measurementCsv());
  options.outPath = path("model.json");
  options.method = "linear";
  options.loss = "huber";
  std::ostringstream out;
  try {
    runCalibrate(options, out);
    FAIL() << "expected a ConfigError";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "--loss");
  }
  EXPECT_TRUE(out.str().empty());  // rejected before any work
  EXPECT_FALSE(fs::exists(options.outPath));
}

}  // namespace
}  // namespace volcomp::calibration
