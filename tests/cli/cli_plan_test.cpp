// `volcomp plan` and `volcomp calibrate` as processes: the criterion option, progress on stderr,
// and a template the written model could not honour refused with one line.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

// A small template: a linear positioning error and a constant pitch of X (3 parameters).
std::string templateText(bool withTravel) {
  nlohmann::json t{{"format", "volcomp-model/1"},
                   {"topology", "FXYZ"},
                   {"tool", {0, 0, 100}},
                   {"error_units", {{"length", "um"}, {"angle", "urad"}}},
                   {"components",
                    {{"EXX", {{"identify", {{"basis", "polynomial"}, {"degree", 1}}}}},
                     {"EBX", {{"identify", "constant"}}}}}};
  if (withTravel) t["travel"] = {{"X", {0, 800}}, {"Y", {0, 500}}, {"Z", {-400, 0}}};
  return t.dump();
}

TEST(CliPlan, TheCriterionIsChosenAndProgressGoesToStderr) {
  TempDir dir;
  const std::string templatePath = quoted(dir.write("template.json", templateText(true)));
  const std::string report = (dir.path() / "plan.json").string();
  for (const char* criterion : {"d", "i"}) {
    SCOPED_TRACE(criterion);
    const CliRun run =
        runCli(dir, "plan " + templatePath + " --grid 5,3,3 --tools '0,0,100;0,0,200' --points 4 " +
                        "--criterion " + criterion + " --report " + quoted(report));
    ASSERT_EQ(run.status, 0) << run.out << run.err;
    const bool i = criterion[0] == 'i';
    EXPECT_NE(run.out.find(i ? "(I-optimal" : "(D-optimal"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("rank 3 of 3"), std::string::npos) << run.out;
    // Progress lines on stderr, the summary alone on stdout.
    EXPECT_NE(run.err.find("exchange pass 1"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("I-optimal exchange") != std::string::npos, i) << run.err;
    EXPECT_EQ(run.out.find("exchange pass"), std::string::npos) << run.out;
    const nlohmann::json plan = nlohmann::json::parse(readFile(report));
    EXPECT_EQ(plan["criterion"].get<std::string>().rfind(i ? "I-optimal" : "D-optimal", 0), 0u);
    EXPECT_EQ(plan["selected"].size(), 4u);
  }
  const CliRun bad = runCli(dir, "plan " + templatePath + " --grid 5,3,3 --points 4 --criterion g");
  EXPECT_EQ(bad.status, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("--criterion"), std::string::npos) << bad.err;
}

TEST(CliCalibrate, APolynomialWithoutTravelIsRefusedWithOneLine) {
  TempDir dir;
  const std::string templatePath = dir.write("template.json", templateText(false));
  const std::string points =
      dir.write("points.csv", "x,y,z,ex,ey,ez\n0,0,0,0,0,0\n400,0,0,0.001,0,0\n800,0,0,0,0,0\n");
  const std::string model = (dir.path() / "model.json").string();
  const CliRun run = runCli(
      dir, "calibrate " + quoted(templatePath) + " " + quoted(points) + " --out " + quoted(model));
  EXPECT_EQ(run.status, 2) << run.out << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find(templatePath), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("components.EXX.identify"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("needs the travel of axis X"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(model));
}

}  // namespace
}  // namespace volcomp::testing
