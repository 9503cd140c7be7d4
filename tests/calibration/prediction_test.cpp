// Propagated uncertainty of predicted errors on a 3-axis template: consistent with the scatter of
// repeated fits, not determined where the data are silent (a tool length never measured when
// pitch and straightness are not separable), and identified curves with their sigma.

#include <gtest/gtest.h>

#include <cmath>

#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
using testing::SyntheticOptions;

// The predicted error at `at` and its sensitivity where the fit's statistics were linearised.
Eigen::Vector3d predict(const IdentificationProblem& problem, const FitResult& fit,
                        const PredictionPoint& at, Eigen::MatrixXd& g) {
  Eigen::Vector3d predicted, ignored;
  problem.prediction(fit.parameters, at, predicted, g);
  problem.prediction(fit.linearisedAt, at, ignored, g);
  return predicted;
}

Eigen::Vector3d trueError(const Eigen::Vector3d& q, const Eigen::Vector3d& tool) {
  const model::MachineModel truth(testing::machineSpec(testing::fxyzTruth()));
  model::Workspace ws;
  return model::evaluate(truth, ws, q, tool).errorMm;
}

TEST(Prediction, SigmaMatchesTheScatterOfRepeatedFits) {
  // 200 data sets: the predicted error at a point between the measured tool lengths scatters
  // around the truth with the propagated sigma: about 95 % within 2 sigma (binomial spread 1.5 %
  // for 200), and the mean of sigma close to the observed spread.
  const Eigen::Vector3d q(333, 222, -111), tool(0, 0, 170);
  const Eigen::Vector3d truth = trueError(q, tool);
  int within = 0, total = 0;
  double sumSquaredDeviation = 0.0, sumVariance = 0.0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    SyntheticOptions options;
    options.noiseMm = 1e-3;
    options.seed = seed;
    options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
    const MeasurementSet data = simulate(testing::machineSpec(testing::fxyzTruth()), options);
    const auto problem =
        makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
    const FitResult fit = solve(*problem, problem->startVector());
    PredictionPoint at;
    at.qMm = q;
    at.toolMm = tool;
    Eigen::MatrixXd g(3, problem->parameterCount());
    const Eigen::Vector3d predicted = predict(*problem, fit, at, g);
    const PredictionUncertainty ux = predictionUncertainty(fit.statistics, g.row(0));
    ASSERT_TRUE(ux.determined);
    const double deviation = predicted.x() - truth.x();
    within += std::abs(deviation) < 2.0 * ux.std ? 1 : 0;
    ++total;
    sumSquaredDeviation += deviation * deviation;
    sumVariance += ux.std * ux.std;
  }
  EXPECT_GT(static_cast<double>(within) / total, 0.9) << within << " of " << total;
  EXPECT_NEAR(std::sqrt(sumSquaredDeviation / total), std::sqrt(sumVariance / total),
              0.2 * std::sqrt(sumVariance / total));
}

TEST(Prediction, AnUnmeasuredToolLengthIsNotDeterminedWhenPitchIsNotSeparable) {
  // One tool length: EBX (pitch) and EXZ's slope and EXX's constant are one combination (see
  // machine_identification_test). Predictions for the measured tool are determined; for another
  // tool length the pitch acts through a different arm and the prediction depends on the
  // combination the data cannot see.
  SyntheticOptions options;
  options.noiseMm = 1e-4;
  const auto [problem, fit] = testing::fitFxyz(options);
  ASSERT_EQ(fit.statistics.rank, 4);
  Eigen::MatrixXd g(3, problem->parameterCount());
  PredictionPoint at;
  at.qMm = Eigen::Vector3d(400, 250, -200);
  at.toolMm = Eigen::Vector3d(0, 0, 100);
  Eigen::Vector3d predicted = predict(*problem, fit, at, g);
  EXPECT_TRUE(predictionUncertainty(fit.statistics, g.row(0)).determined);
  EXPECT_NEAR(predicted.x(), trueError(at.qMm, *at.toolMm).x(), 1e-3);
  at.toolMm = Eigen::Vector3d(0, 0, 250);
  predicted = predict(*problem, fit, at, g);
  const PredictionUncertainty other = predictionUncertainty(fit.statistics, g.row(0));
  EXPECT_FALSE(other.determined);
  EXPECT_TRUE(std::isnan(other.std));
}

TEST(Prediction, CurvesCarryTheirSigmaAndTheirShapeWhereTheConstantIsShared) {
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
  const auto [problem, fit] = testing::fitFxyz(options);
  const std::vector<Curve> curves = problem->curves();
  ASSERT_EQ(curves.size(), 3u);  // EBX, EXX, EXZ (location errors are not curves)
  const Curve& exx = curves[1];
  EXPECT_EQ(exx.component, "EXX");
  EXPECT_EQ(exx.unit, "um");
  // Polynomials: five positions over the travel.
  ASSERT_EQ(exx.positionsMm, (std::vector<double>{0, 200, 400, 600, 800}));
  for (std::size_t k = 0; k < exx.positionsMm.size(); ++k) {
    const double value = exx.gradients[k].dot(fit.parameters);
    const PredictionUncertainty u = functionUncertainty(fit.statistics, exx.gradients[k]);
    ASSERT_TRUE(u.determined);
    EXPECT_NEAR(value, 3e-3 + 12e-6 * exx.positionsMm[k], 4.0 * u.std);
  }
}

}  // namespace
}  // namespace volcomp::calibration
