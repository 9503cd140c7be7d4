// `volcomp calibrate` as a process, on files: output model, report JSON, summary, exit status
// and the one line on stderr.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_cli.hpp"
#include "synthetic.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
using volcomp::testing::CliRun;
using volcomp::testing::quoted;
namespace fs = std::filesystem;

// The command line of one run: the files and the other options as CLI text.
struct CalibrateOptions {
  std::string templatePath;
  std::string measurementsPath;
  std::string outPath;
  std::string reportPath;
  std::string validatePath;
  std::string predictPath;
  std::string predictOutPath;
  std::string more;  ///< further options, e.g. "--loss cauchy"
};

class RunCalibrate : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return directory_.write(name, text);
  }
  std::string path(const std::string& name) const { return (directory_.path() / name).string(); }

  CliRun runCalibrate(const CalibrateOptions& options) const {
    std::string args = "calibrate " + quoted(options.templatePath) + " " +
                       quoted(options.measurementsPath) + " --out " + quoted(options.outPath);
    if (!options.reportPath.empty()) args += " --report " + quoted(options.reportPath);
    if (!options.validatePath.empty()) args += " --validate " + quoted(options.validatePath);
    if (!options.predictPath.empty()) {
      args += " --predict " + quoted(options.predictPath) + " --predict-out " +
              quoted(options.predictOutPath);
    }
    if (!options.more.empty()) args += " " + options.more;
    return volcomp::testing::runCli(directory_, args);
  }

  // Measurements of the FXYZ truth below with two tool lengths, as CSV text.
  static std::string measurementCsv(unsigned seed = 1) {
    json truth = testing::fxyzTruth();
    truth["components"].erase("EC0Y");
    testing::SyntheticOptions options;
    options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
    options.noiseMm = 5e-4;
    options.seed = seed;
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
           {"travel", {{"X", {0, 800}}, {"Y", {0, 500}}, {"Z", {-400, 0}}}},
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

  static json readJson(const std::string& file) {
    std::ifstream in(file);
    return json::parse(in);
  }

  CalibrateOptions defaults(bool withStraightness = false) {
    CalibrateOptions options;
    options.templatePath = write("template.json", templateText(withStraightness));
    options.measurementsPath = write("points.csv", measurementCsv());
    options.outPath = path("model.json");
    options.reportPath = path("report.json");
    return options;
  }

  volcomp::testing::TempDir directory_;
};

TEST_F(RunCalibrate, WritesALoadableModelAReportAndASummary) {
  const CalibrateOptions options = defaults();
  const CliRun out = runCalibrate(options);
  EXPECT_EQ(out.status, 0) << out.out << out.err;

  // The output is an ordinary model file (no identify blocks), in the template's units.
  const config::ModelDocument model = config::loadModelFile(options.outPath);
  EXPECT_TRUE(model.identify.empty());
  EXPECT_EQ(model.units.length, config::LengthUnit::Micrometre);
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

  const std::string summary = out.out;
  EXPECT_NE(summary.find("EXZ c1"), std::string::npos) << summary;
  EXPECT_NE(summary.find("rank 4 of 4"), std::string::npos) << summary;
  EXPECT_NE(summary.find("residual |e| before"), std::string::npos) << summary;
  EXPECT_NE(summary.find("iteration 1"), std::string::npos) << summary;  // progress
}

TEST_F(RunCalibrate, NamesWhatTheDataCannotSeparate) {
  const CalibrateOptions options = defaults(true);
  const CliRun out = runCalibrate(options);
  EXPECT_EQ(out.status, 0) << out.out << out.err;
  const json report = readJson(options.reportPath);
  EXPECT_EQ(report["rank"], 4);
  ASSERT_EQ(report["unidentifiable"].size(), 1u);
  const json& names = report["unidentifiable"][0]["parameters"];
  EXPECT_EQ(names, (json{"EXX c0", "EXY c0"})) << report["unidentifiable"].dump();
  EXPECT_NE(out.out.find("EXX c0 and EXY c0 are not separable"), std::string::npos) << out.out;
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
  options.more = "--loss cauchy --loss-scale 0.002";
  const CliRun out = runCalibrate(options);
  EXPECT_EQ(out.status, 0) << out.out << out.err;
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
  // A ConfigError: exit status 2, one line on stderr naming the file.
  const CliRun run = runCalibrate(options);
  EXPECT_EQ(run.status, 2) << run.out << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("nothing to identify"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.rfind("volcomp: " + options.templatePath + ": ", 0), 0u) << run.err;
  EXPECT_FALSE(fs::exists(options.outPath));
}

TEST_F(RunCalibrate, APolynomialWithoutTravelIsRefusedBeforeAnythingIsWritten) {
  // The model reader refuses such a polynomial: calibrate refuses the template instead of
  // writing a model nobody can load.
  json t = json::parse(templateText(false));
  t.erase("travel");
  CalibrateOptions options = defaults();
  options.templatePath = write("template.json", t.dump());
  const CliRun run = runCalibrate(options);
  EXPECT_EQ(run.status, 2) << run.out << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_EQ(run.err.rfind("volcomp: " + options.templatePath + ": components.EXX.identify: ", 0),
            0u)
      << run.err;
  EXPECT_NE(run.err.find("needs the travel of axis X"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(options.outPath));
  EXPECT_FALSE(fs::exists(options.reportPath));
}

TEST_F(RunCalibrate, RobustLossWithTheLinearMethodIsAnOptionError) {
  CalibrateOptions options;
  options.templatePath = write("template.json", templateText(false));
  options.measurementsPath = write("points.csv", measurementCsv());
  options.outPath = path("model.json");
  options.more = "--method linear --loss huber";
  const CliRun run = runCalibrate(options);
  EXPECT_EQ(run.status, 2) << run.out << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_EQ(run.err.rfind("volcomp: command line: --loss: ", 0), 0u) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;  // rejected before any work
  EXPECT_FALSE(fs::exists(options.outPath));
}

TEST_F(RunCalibrate, TheModelRecordsItsProvenanceAndMeasuredTools) {
  CalibrateOptions options = defaults(true);
  const CliRun out = runCalibrate(options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  const config::ModelDocument model = config::loadModelFile(options.outPath);
  ASSERT_TRUE(model.calibration.has_value());
  const config::CalibrationRecord& record = *model.calibration;
  EXPECT_EQ(record.volcompVersion, VOLCOMP_VERSION);
  EXPECT_EQ(record.date.size(), 20u) << record.date;  // 2026-12-01T19:40:00Z
  EXPECT_EQ(record.templateFile, options.templatePath);
  EXPECT_EQ(record.measurementFiles, std::vector<std::string>{options.measurementsPath});
  EXPECT_EQ(record.points, 200);
  EXPECT_EQ(record.parameterCount, 5);
  EXPECT_EQ(record.rank, 4);
  EXPECT_GT(*record.residualRmsBeforeMm, *record.residualRmsAfterMm);
  EXPECT_NEAR(*record.s0Mm, 5e-4, 1e-4);
  EXPECT_EQ(record.notIdentifiable, (std::vector<std::string>{"EXX c0", "EXY c0"}));
  EXPECT_EQ(record.toolsMm,
            (std::vector<Eigen::Vector3d>{Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)}));
  EXPECT_NEAR(*config::toolDistanceMm(record, Eigen::Vector3d(0, 0, 300)), 50.0, 1e-9);
  // The report: no sigma where not identifiable, the decision and the policy stated.
  const json report = readJson(options.reportPath);
  EXPECT_EQ(report["volcomp_version"], VOLCOMP_VERSION);
  for (const json& p : report["parameters"]) {
    EXPECT_EQ(p["std"].is_null(), !p["identifiable"].get<bool>()) << p.dump();
  }
  EXPECT_EQ(report["identifiability"]["projection_threshold"], kIdentifiabilityThreshold);
  EXPECT_NE(report["identifiability"]["policy"].get<std::string>().find("minimum-norm change"),
            std::string::npos);
  const json& physical = report["unidentifiable"][0]["physical"];
  EXPECT_EQ(physical["pivot"].get<std::string>().substr(0, 2), "EX");
  EXPECT_NE(physical["description"].get<std::string>().find("1 um of EX"), std::string::npos)
      << physical.dump();
  EXPECT_EQ(report["tools_mm"].size(), 2u);
  EXPECT_EQ(report["residuals"]["after"]["axes"]["rms_mm"].size(), 3u);
  EXPECT_EQ(report["prediction"]["measured"]["coverage_factor"], 2.0);
  EXPECT_EQ(report["prediction"]["measured"]["undetermined"], 0);
  EXPECT_GT(report["prediction"]["measured"]["max_std_mm"].get<double>(), 0.0);
  EXPECT_EQ(report["curves"].size(), 4u);  // EBX, EXX, EXY, EXZ
}

TEST_F(RunCalibrate, FarTooFewPointsAreRefusedWithASummaryUnlessForced) {
  CalibrateOptions options = defaults();
  options.measurementsPath = write("one.csv", "x,y,z,ex,ey,ez\n100,100,-100,0.001,0,0\n");
  const CliRun out = runCalibrate(options);
  EXPECT_EQ(out.status, 2) << out.out << out.err;  // a refusal
  EXPECT_EQ(out.errLines(), 1) << out.err;
  EXPECT_NE(out.err.find("identify 1 of 4"), std::string::npos) << out.err;
  EXPECT_NE(out.err.find("--force"), std::string::npos) << out.err;
  EXPECT_FALSE(fs::exists(options.outPath));
  // The summary says per component what is missing and what the data cover, in a few lines.
  const std::string summary = out.out;
  EXPECT_NE(summary.find("components.EXX: 2 of 2 not identifiable"), std::string::npos) << summary;
  EXPECT_NE(summary.find("the data: 1 point, X 100..100 mm"), std::string::npos) << summary;
  options.more = "--force";
  const CliRun forced = runCalibrate(options);
  EXPECT_EQ(forced.status, 0) << forced.out << forced.err;
  EXPECT_TRUE(fs::exists(options.outPath));
}

TEST_F(RunCalibrate, HeldOutResidualsBesideTheFit) {
  CalibrateOptions options = defaults();
  options.validatePath = write("check.csv", measurementCsv(2));
  const CliRun out = runCalibrate(options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  const json validation = readJson(options.reportPath)["residuals"]["validation"];
  EXPECT_EQ(validation["kind"], "file");
  EXPECT_EQ(validation["points"], 200);
  // Independent noise of 0.5 um per coordinate: |e| RMS about 0.5 sqrt(3) = 0.87 um.
  EXPECT_NEAR(validation["rms_mm"].get<double>(), 0.87e-3, 0.15e-3);
  EXPECT_NE(out.out.find("residual |e| held out (" + options.validatePath), std::string::npos)
      << out.out;
  EXPECT_EQ(config::loadModelFile(options.outPath).calibration->validationFile,
            options.validatePath);

  CalibrateOptions folds = defaults();
  folds.more = "--k-fold 5";
  const CliRun foldOut = runCalibrate(folds);
  ASSERT_EQ(foldOut.status, 0) << foldOut.out << foldOut.err;
  const json kfold = readJson(folds.reportPath)["residuals"]["validation"];
  EXPECT_EQ(kfold["kind"], "k-fold");
  EXPECT_EQ(kfold["folds"], 5);
  EXPECT_EQ(kfold["points"], 200);
  EXPECT_EQ(kfold["fold_rank"], json({4, 4, 4, 4, 4}));
  EXPECT_NEAR(kfold["rms_mm"].get<double>(), 0.87e-3, 0.15e-3);
}

TEST_F(RunCalibrate, PredictionsWithUncertaintyAtAnyPoint) {
  CalibrateOptions options = defaults();
  options.predictPath = write("at.csv",
                              "# x, y, z and the tool\n"
                              "x,y,z,tx,ty,tz\n"
                              "400,250,-200,0,0,170\n"
                              "400,250,-200,0,0,400\n");
  options.predictOutPath = path("predicted.csv");
  const CliRun out = runCalibrate(options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  std::ifstream in(options.predictOutPath);
  std::string header, inside, outside;
  std::getline(in, header);
  std::getline(in, inside);
  std::getline(in, outside);
  EXPECT_EQ(header, "x,y,z,tx,ty,tz,ex,ey,ez,ux,uy,uz,k,determined");
  EXPECT_EQ(inside.substr(inside.size() - 4), ",2,1") << inside;
  // Two tool lengths separate the pitch: a third length is extrapolated, but determined.
  EXPECT_EQ(outside.substr(outside.size() - 4), ",2,1") << outside;
  const json at = readJson(options.reportPath)["prediction"]["at"];
  ASSERT_EQ(at.size(), 2u);
  EXPECT_EQ(at[0]["line"], 3);
  EXPECT_LT(at[0]["std_mm"][0].get<double>(), at[1]["std_mm"][0].get<double>())
      << "extrapolating to a longer tool is less certain";
}

TEST_F(RunCalibrate, ArcsecondsOnScreenOnRequest) {
  CalibrateOptions options = defaults();
  options.more = "--angle-unit arcsec";
  const CliRun out = runCalibrate(options);
  ASSERT_EQ(out.status, 0) << out.out << out.err;
  // EBX = 25 urad = 5.157 arcsec, shown to 4 significant digits.
  EXPECT_NE(out.out.find("arcsec"), std::string::npos);
  EXPECT_NE(out.out.find(" 5.1"), std::string::npos) << out.out;
}

}  // namespace
}  // namespace volcomp::calibration
