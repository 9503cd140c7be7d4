// Bidirectional tables in one fit: measurements approached in + and - (direction column)
// identify `values` and `values_negative` of a positioning error together, with the reversal and
// its sigma.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"

namespace volcomp::calibration {
namespace {

using model::Direction;
using nlohmann::json;
using testing::SyntheticOptions;

const std::vector<double> kNodes{0, 200, 400, 600, 800};
const std::vector<double> kPositive{0, 4, 7, 9, 14};
const std::vector<double> kNegative{4, 8.5, 11, 13.5, 18};  // reversal about 4.5 um

json truthModel() {
  return json{{"format", "volcomp-model/1"},
              {"topology", "XYFZ"},
              {"tool", {0, 0, 120}},
              {"travel", {{"X", {0, 800}}, {"Y", {0, 500}}, {"Z", {-400, 0}}}},
              {"error_units", {{"length", "um"}, {"angle", "urad"}}},
              {"components",
               {{"EXX",
                 {{"positions", kNodes},
                  {"values", kPositive},
                  {"values_negative", kNegative},
                  {"interpolation", "cubic"}}},
                {"EYY", {{"polynomial", {0, 0.01}}}}}}};
}

json templateModel() {
  json t = truthModel();
  t["components"]["EXX"] = {{"identify",
                             {{"basis", "table"},
                              {"positions", kNodes},
                              {"interpolation", "cubic"},
                              {"bidirectional", true}}}};
  return t;
}

MeasurementSet measure() {
  SyntheticOptions options;
  options.noiseMm = 5e-4;
  options.x = {0, 100, 200, 300, 400, 500, 600, 700, 800};
  options.tools = {Eigen::Vector3d(0, 0, 120)};
  // X approached from below and from above (ISO 230-2 runs), Y and Z in +.
  options.directions = {{Direction::Positive, Direction::Positive, Direction::Positive},
                        {Direction::Negative, Direction::Positive, Direction::Positive}};
  return simulate(testing::machineSpec(truthModel()), options);
}

TEST(Bidirectional, BothCurvesAndTheReversalInOneFit) {
  const MeasurementSet data = measure();
  EXPECT_TRUE(data.hasDirection);
  const auto problem = makeIdentificationProblem(testing::templateDocument(templateModel()), data);
  ASSERT_EQ(problem->parameterCount(), 10);
  EXPECT_EQ(problem->parameterInfo()[1].name, "EXX+[200]");
  EXPECT_EQ(problem->parameterInfo()[6].name, "EXX-[200]");
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 10);
  for (std::size_t k = 0; k < kNodes.size(); ++k) {
    const auto j = static_cast<Eigen::Index>(k);
    EXPECT_NEAR(fit.parameters(j), kPositive[k] * 1e-3, 4.0 * fit.statistics.standardDeviation(j));
    EXPECT_NEAR(fit.parameters(j + 5), kNegative[k] * 1e-3,
                4.0 * fit.statistics.standardDeviation(j + 5));
  }
  // The written model carries both curves.
  const json model = problem->modelJson(fit.parameters);
  ASSERT_TRUE(model["components"]["EXX"].contains("values_negative"));
  EXPECT_NEAR(model["components"]["EXX"]["values_negative"][2].get<double>(), 11.0, 0.1);
  // The reversal per node with its sigma: var(neg - pos) = var(neg) + var(pos) - 2 cov.
  const std::vector<Curve> curves = problem->curves();
  ASSERT_EQ(curves.size(), 3u);
  EXPECT_EQ(curves[0].direction, CurveDirection::Positive);
  EXPECT_EQ(curves[1].direction, CurveDirection::Negative);
  EXPECT_STREQ(curveDirectionName(curves[0].direction), "+");
  EXPECT_STREQ(curveDirectionName(curves[1].direction), "-");
  const Curve& reversal = curves[2];
  EXPECT_EQ(reversal.direction, CurveDirection::Reversal);
  EXPECT_STREQ(curveDirectionName(reversal.direction), "reversal");
  for (std::size_t k = 0; k < kNodes.size(); ++k) {
    const double value = reversal.gradients[k].dot(fit.parameters);
    const auto j = static_cast<Eigen::Index>(k);
    const auto& c = fit.statistics.covariance;
    const double sigma = std::sqrt(c(j, j) + c(j + 5, j + 5) - 2.0 * c(j, j + 5));
    const PredictionUncertainty u = functionUncertainty(fit.statistics, reversal.gradients[k]);
    EXPECT_NEAR(u.std, sigma, 1e-12 + 1e-9 * sigma);
    EXPECT_NEAR(value, (kNegative[k] - kPositive[k]) * 1e-3, 4.0 * sigma);
  }
}

TEST(Bidirectional, OneDirectionOnlyLeavesTheOtherCurveUnidentifiable) {
  MeasurementSet data = measure();
  std::erase_if(data.points,
                [](const Measurement& m) { return m.directions[0] == Direction::Negative; });
  const auto problem = makeIdentificationProblem(testing::templateDocument(templateModel()), data);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 5);
  for (int j = 5; j < 10; ++j) {
    EXPECT_FALSE(fit.statistics.identifiable[static_cast<std::size_t>(j)]) << fit.names[j];
    EXPECT_NE(fit.statistics.unidentifiable[static_cast<std::size_t>(j - 5)].description.find(
                  "has no effect on the measured data"),
              std::string::npos);
  }
}

TEST(Bidirectional, UnknownDirectionMeasuresTheMeanOfBothCurves) {
  // The model's rule where no direction is known: the mean of the two curves. Points without a
  // direction column see half of each curve, so with only such points the two are not
  // separable (their difference is the combination) but their mean is determined.
  MeasurementSet data = measure();
  for (Measurement& m : data.points) m.directions = model::Directions{};
  const auto problem = makeIdentificationProblem(testing::templateDocument(templateModel()), data);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 5);
  EXPECT_EQ(fit.statistics.unidentifiable.size(), 5u);
  Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(10);
  mean(2) = mean(7) = 0.5;
  EXPECT_TRUE(functionUncertainty(fit.statistics, mean).determined);
}

TEST(Bidirectional, DirectionColumnInTheMeasurementCsv) {
  std::istringstream input(
      "x,y,z,ex,ey,ez,direction\n"
      "100,0,-100,0.001,0,0,+++\n"
      "100,0,-100,0.005,0,0,\"-,+,+\"\n");
  const MeasurementSet set = parseMeasurementsCsv(input, "points.csv");
  EXPECT_TRUE(set.hasDirection);
  EXPECT_EQ(set.points[1].directions[0], Direction::Negative);
  EXPECT_EQ(set.points[1].directions[1], Direction::Positive);
}

}  // namespace
}  // namespace volcomp::calibration
