// D-H deviations (Bulla Ramos et al.'s Cartesian table) identified with Levenberg-Marquardt.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

#include "dh_synthetic.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
constexpr double kDeg = std::numbers::pi / 180.0;

using testing::seedChain;
using testing::simulateChain;

config::ModelDocument chainTemplate(const json& t) {
  config::ParseOptions options;
  options.allowIdentify = true;
  return config::parseModel(t, "chain-template.json", options);
}

TEST(DhIdentification, DeviationsRecoveredWithinThreeSigma) {
  const json truth = seedChain();
  json t = truth;
  auto& links = t["chain"]["links"];
  links[0]["da"] = {{"identify", "constant"}};
  links[1]["dalpha"] = {{"identify", "constant"}};
  links[2]["dalpha"] = {{"identify", "constant"}, {"start", 0.0}};
  links[1]["da"] = {{"identify", "constant"}};
  const double noise = 1e-4;
  const auto problem = makeIdentificationProblem(chainTemplate(t), simulateChain(truth, noise, 5));
  EXPECT_FALSE(problem->nearlyLinear());
  SolveOptions options;
  options.method = Method::LevenbergMarquardt;
  const FitResult fit = solve(*problem, problem->startVector(), options);
  ASSERT_TRUE(fit.converged) << fit.termination;
  ASSERT_EQ(fit.names, (std::vector<std::string>{"links[0].da", "links[1].da", "links[1].dalpha",
                                                 "links[2].dalpha"}));
  EXPECT_EQ(fit.statistics.rank, 4);
  const std::vector<double> expected{0.012, -0.008, -0.0013544 * kDeg, 0.0010835 * kDeg};
  for (int j = 0; j < 4; ++j) {
    EXPECT_LT(std::abs(fit.parameters(j) - expected[static_cast<std::size_t>(j)]),
              3.0 * fit.statistics.standardDeviation(j))
        << fit.names[j] << " = " << fit.parameters(j) << " +- "
        << fit.statistics.standardDeviation(j);
  }
  // 300 rows - 4 parameters: s0 / sigma spread 4 %.
  EXPECT_NEAR(std::sqrt(fit.statistics.varianceFactor), noise, 0.2 * noise);
  // The report shows angles in degrees like the file.
  EXPECT_EQ(problem->parameterInfo()[2].unit, "deg");
  // The identified chain is written with the fitted deviations (degrees).
  const json written = problem->modelJson(fit.parameters);
  EXPECT_NEAR(written["chain"]["links"][1]["dalpha"].get<double>(), fit.parameters(2) / kDeg,
              1e-12);
}

TEST(DhIdentification, RotationAboutTheToolArmIsNamedUnidentifiable) {
  // A constant rotation of the fixed tool arm r (link 4: d = 150 along z, a = 30 along x) moves
  // the tip by w x r: the component of w along r moves nothing, so the three rotation deviations
  // of link 3 are determined only up to that direction.
  const json truth = seedChain();
  json t = truth;
  t["chain"]["links"][3]["drotation_deg"] = {{"identify", "constant"}};
  const auto problem = makeIdentificationProblem(chainTemplate(t), simulateChain(truth, 1e-4, 9));
  SolveOptions options;
  options.method = Method::LevenbergMarquardt;
  const FitResult fit = solve(*problem, problem->startVector(), options);
  EXPECT_EQ(fit.statistics.parameterCount, 3);
  EXPECT_EQ(fit.statistics.rank, 2);
  ASSERT_EQ(fit.statistics.unidentifiable.size(), 1u);
  std::set<std::string> names;
  for (const auto& [index, coefficient] : fit.statistics.unidentifiable[0].terms) {
    names.insert(fit.names[index]);
  }
  // The arm (30, 0, 150) has x and z parts: rotations about x and z together.
  EXPECT_EQ(names,
            (std::set<std::string>{"links[3].drotation_deg[x]", "links[3].drotation_deg[z]"}))
      << fit.statistics.unidentifiable[0].description;
}

TEST(DhIdentification, JointColumnCountMustMatchTheChain) {
  json t = seedChain();
  t["chain"]["links"][0]["da"] = {{"identify", "constant"}};
  MeasurementSet data = simulateChain(seedChain(), 0.0, 1);
  data.jointColumns = 2;
  try {
    makeIdentificationProblem(chainTemplate(t), data);
    FAIL() << "expected a ConfigError";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("q1..q3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace volcomp::calibration
