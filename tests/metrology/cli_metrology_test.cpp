// `volcomp iso230-2` and `volcomp export` end to end: exit statuses, one-line errors, the files.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "../cli/run_cli.hpp"

namespace volcomp::testing {
namespace {

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

TEST(CliIso230, EvaluatesTheExampleAndWritesJsonAndAModel) {
  TempDir dir;
  const std::string json = (dir.path() / "r.json").string();
  const std::string model = (dir.path() / "m.json").string();
  const CliRun run = runCli(dir, "iso230-2 " + quoted(kExamples + "/iso230-2-x-runs.csv") +
                                     " --json " + quoted(json) + " --model-out " + quoted(model) +
                                     " --merge " + quoted(kExamples + "/vmc-xyfz-21.json"));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_NE(run.out.find("9 targets, 5 runs ↑, 5 runs ↓"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("accuracy A"), std::string::npos);
  EXPECT_NE(run.out.find("EXX = -x̄"), std::string::npos);
  const nlohmann::json result = nlohmann::json::parse(readFile(json));
  EXPECT_EQ(result.at("format"), "volcomp-iso230-2/1");
  EXPECT_EQ(result.at("targets").size(), 9u);
  // The merged model keeps the example's other components and units and checks clean.
  const nlohmann::json merged = nlohmann::json::parse(readFile(model));
  EXPECT_EQ(merged.at("topology"), "XYFZ");
  EXPECT_TRUE(merged.at("components").contains("EBX"));
  EXPECT_EQ(merged.at("components").at("EXX").at("positions").size(), 9u);
  const double meanUp0 = result.at("targets")[0].at("mean_positive").get<double>();
  EXPECT_NEAR(merged.at("components").at("EXX").at("values")[0].get<double>(), -meanUp0 * 1000,
              1e-9);
  EXPECT_EQ(runCli(dir, "check " + quoted(model)).status, 0);
}

// The whole chain keeps the sign: a laser curve x̄ measured on the workpiece-side X of an XYFZ
// machine goes into the model as EXX = -x̄ and comes out of the LinuxCNC export (type 0: where the
// joint really is) as nominal + x̄, forward from x̄↑ and reverse from x̄↓, interpolated linearly
// between the targets.
TEST(CliIso230, MeasuredCurveComesBackInTheLinuxCncTable) {
  TempDir dir;
  const std::string json = (dir.path() / "r.json").string();
  const std::string model = (dir.path() / "exx.json").string();
  ASSERT_EQ(runCli(dir, "iso230-2 " + quoted(kExamples + "/iso230-2-x-runs.csv") + " --json " +
                            quoted(json) + " --model-out " + quoted(model) + " --topology XYFZ")
                .status,
            0);
  const CliRun exported = runCli(dir, "export " + quoted(model) +
                                          " --format linuxcnc --comp-type 0 "
                                          "--out " +
                                          quoted((dir.path() / "l").string()));
  ASSERT_EQ(exported.status, 0) << exported.err;
  const nlohmann::json result = nlohmann::json::parse(readFile(json));
  std::vector<double> targets, up, down;
  for (const nlohmann::json& t : result.at("targets")) {
    targets.push_back(t.at("position").get<double>());
    up.push_back(t.at("mean_positive").get<double>());
    down.push_back(t.at("mean_negative").get<double>());
  }
  const auto interpolate = [&](const std::vector<double>& values, double q) {
    std::size_t i = 0;
    while (i + 2 < targets.size() && q > targets[i + 1]) ++i;
    const double t = (q - targets[i]) / (targets[i + 1] - targets[i]);
    return values[i] + t * (values[i + 1] - values[i]);
  };
  std::istringstream lines(readFile(dir.path() / "l" / "joint0.comp"));
  double nominal = 0, forward = 0, reverse = 0;
  int rows = 0;
  while (lines >> nominal >> forward >> reverse) {
    EXPECT_NEAR(forward - nominal, interpolate(up, nominal), 2e-7) << nominal;
    EXPECT_NEAR(reverse - nominal, interpolate(down, nominal), 2e-7) << nominal;
    ++rows;
  }
  EXPECT_EQ(rows, 86);
}

TEST(CliIso230, RefusalsAreOneLineWithStatusTwo) {
  TempDir dir;
  const std::string csv = dir.write("few.csv",
                                    "run,direction,target_mm,deviation_um\n"
                                    "1,+,0,1\n1,+,10,1\n1,+,25,1\n1,+,31,1\n1,+,50,1\n");
  const CliRun run = runCli(dir, "iso230-2 " + quoted(csv));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1);
  EXPECT_NE(run.err.find("1 run(s) in the positive"), std::string::npos) << run.err;
  EXPECT_EQ(run.out, "");
  const CliRun noTopology = runCli(dir, "iso230-2 " + quoted(csv) + " --model-out x.json");
  EXPECT_EQ(noTopology.status, 2);
  EXPECT_NE(noTopology.err.find("needs exactly one of --topology and --merge"), std::string::npos);
  const CliRun badTopology = runCli(dir, "iso230-2 " + quoted(kExamples + "/iso230-2-x-runs.csv") +
                                             " --model-out x.json --topology XYZ");
  EXPECT_EQ(badTopology.status, 2);
  EXPECT_EQ(badTopology.out, "");
  EXPECT_NE(badTopology.err.find("--topology"), std::string::npos) << badTopology.err;
}

// Every refusal about the --model-out file names it, in one line under 300 characters: no
// --topology or --merge, runs without an axis column, a directory or an input as the target.
TEST(CliIso230, ModelOutRefusalsNameTheFile) {
  TempDir dir;
  const std::string runs = kExamples + "/iso230-2-x-runs.csv";
  const std::string model = (dir.path() / "m.json").string();
  const auto expectRefusal = [&](const std::string& args, const std::string& file,
                                 const std::string& fragment) {
    const CliRun run = runCli(dir, "iso230-2 " + args);
    EXPECT_EQ(run.status, 2) << run.err;
    EXPECT_EQ(run.errLines(), 1) << run.err;
    EXPECT_NE(run.err.find("--model-out " + file), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(fragment), std::string::npos) << run.err;
    EXPECT_LE(run.err.size(), 300u) << run.err;
  };
  expectRefusal(quoted(runs) + " --model-out " + quoted(model), model,
                "needs exactly one of --topology and --merge");
  // The example's runs without their axis column.
  std::istringstream in(readFile(runs));
  std::string csv;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') csv += line.substr(line.find(',') + 1) + "\n";
  }
  const std::string noAxis = dir.write("no-axis.csv", csv);
  expectRefusal(quoted(noAxis) + " --model-out " + quoted(model) + " --topology XYFZ", model,
                noAxis + " has no axis column");
  const std::string directory = (dir.path() / "out").string();
  std::filesystem::create_directory(directory);
  expectRefusal(quoted(runs) + " --model-out " + quoted(directory) + " --topology XYFZ", directory,
                "is a directory");
  expectRefusal(quoted(noAxis) + " --axis X --model-out " + quoted(noAxis) + " --topology XYFZ",
                noAxis, "is the input");
}

TEST(CliExport, WritesEachFormatAndReportsTheRemainingError) {
  TempDir dir;
  const std::string model = quoted(kExamples + "/vmc-xyfz-21.json");
  const CliRun linuxcnc = runCli(
      dir, "export " + model + " --format linuxcnc --out " + quoted((dir.path() / "l").string()));
  ASSERT_EQ(linuxcnc.status, 0) << linuxcnc.err;
  EXPECT_NE(linuxcnc.out.find("EXX -> joint of X: forward column from values"), std::string::npos);
  EXPECT_NE(linuxcnc.out.find("EBX: angular error motion"), std::string::npos);
  EXPECT_NE(linuxcnc.out.find("these tables only"), std::string::npos);
  EXPECT_NE(linuxcnc.out.find("live (volcompd)"), std::string::npos);
  EXPECT_NE(readFile(dir.path() / "l" / "comp.ini").find("COMP_FILE = joint0.comp"),
            std::string::npos);
  const std::string joint0 = readFile(dir.path() / "l" / "joint0.comp");
  EXPECT_EQ(std::count(joint0.begin(), joint0.end(), '\n'), 86);
  EXPECT_EQ(joint0.find('#'), std::string::npos);  // LinuxCNC stops at a comment line

  const CliRun siemens = runCli(dir, "export " + model +
                                         " --format siemens --axis-names X1,Y1,Z1 "
                                         "--out " +
                                         quoted((dir.path() / "s").string()));
  ASSERT_EQ(siemens.status, 0) << siemens.err;
  EXPECT_NE(readFile(dir.path() / "s" / "AX_EEC.INI").find("$AA_ENC_COMP_STEP[0,X1]=10.0"),
            std::string::npos);
  EXPECT_NE(readFile(dir.path() / "s" / "NC_CEC.INI").find("$AN_CEC_DIRECTION[1]=-1"),
            std::string::npos);

  const CliRun csv = runCli(dir, "export " + model +
                                     " --format csv --component EBX --step 50 "
                                     "--out " +
                                     quoted((dir.path() / "ebx.csv").string()));
  ASSERT_EQ(csv.status, 0) << csv.err;
  EXPECT_EQ(readFile(dir.path() / "ebx.csv").rfind("position_mm,value_urad\n0.0,", 0), 0u);
}

TEST(CliExport, BadArgumentsAreOneLineWithStatusTwo) {
  TempDir dir;
  const std::string model = quoted(kExamples + "/vmc-xyfz-21.json");
  for (const std::string& args :
       {std::string("--format csv --component EQQ --out x.csv"),
        std::string("--format csv --out x.csv"), std::string("--format linuxcnc --step 1 --out l"),
        std::string("--format linuxcnc --step Q=3 --out l"),
        std::string("--format siemens --axis-names AX1 --out s")}) {
    const CliRun run = runCli(dir, "export " + model + " " + args);
    EXPECT_EQ(run.status, 2) << args;
    EXPECT_EQ(run.errLines(), 1) << args << ": " << run.err;
  }
  const CliRun chain = runCli(dir, "export " + quoted(kExamples + "/cartesian-table-dh.json") +
                                       " --format linuxcnc --out l");
  EXPECT_EQ(chain.status, 2);
  EXPECT_NE(chain.err.find("D-H chain"), std::string::npos);
}

}  // namespace
}  // namespace volcomp::testing
