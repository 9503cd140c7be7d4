// 3-axis identification: synthetic round trips, rank analysis, instrument frame.

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"

namespace volcomp::calibration {
namespace {

using nlohmann::json;
using testing::SyntheticOptions;

std::string parameterName(const IdentificationProblem& problem, Eigen::Index j) {
  return problem.parameterInfo()[static_cast<std::size_t>(j)].name;
}

std::set<std::string> namesOf(const Combination& combination, const FitResult& fit) {
  std::set<std::string> names;
  for (const auto& [index, coefficient] : combination.terms) names.insert(fit.names[index]);
  return names;
}

// Checks every identified parameter against its true value: at most `allowedBeyond3` beyond 3 sigma
// and none beyond 4 sigma (for n Gaussian estimates, P(any beyond 3 sigma) = 1 - 0.9973^n is
// large for big n, P(any beyond 4 sigma) = n * 6.3e-5 is not).
void expectWithinSigma(const FitResult& fit, const Eigen::VectorXd& truth, int allowedBeyond3) {
  int beyond3 = 0;
  for (Eigen::Index j = 0; j < truth.size(); ++j) {
    const double sigma = fit.statistics.standardDeviation(j);
    const double deviation = std::abs(fit.parameters(j) - truth(j));
    EXPECT_LT(deviation, 4.0 * sigma)
        << fit.names[static_cast<std::size_t>(j)] << " = " << fit.parameters(j) << " +- " << sigma
        << ", true " << truth(j);
    beyond3 += deviation > 3.0 * sigma ? 1 : 0;
  }
  EXPECT_LE(beyond3, allowedBeyond3);
}

TEST(MachineIdentification, SingleToolLengthCannotSeparatePitchFromStraightnessAndOffset) {
  // With one tool length, EBX = b gives e_x = b (z + 100) (Abbe arm from the X carriage to the
  // tool tip, the worked example of docs/model-file.md), which is exactly EXX c0 = 100 b plus EXZ
  // c1 = b: the direction (EBX +1, EXZ c1 -1, EXX c0 -100) in raw units leaves every residual
  // unchanged.
  SyntheticOptions options;
  options.noiseMm = 1e-4;
  const MeasurementSet data = simulate(testing::machineSpec(testing::fxyzTruth()), options);
  const auto problem =
      makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.parameterCount, 5);
  EXPECT_EQ(fit.statistics.rank, 4);
  ASSERT_EQ(fit.statistics.unidentifiable.size(), 1u);
  const Combination& combination = fit.statistics.unidentifiable[0];
  EXPECT_EQ(namesOf(combination, fit), (std::set<std::string>{"EBX", "EXZ c1", "EXX c0"}))
      << combination.description;
  EXPECT_NE(combination.description.find("not separable"), std::string::npos);
  // The data are still fitted down to the noise: the unseen direction does not matter for them.
  EXPECT_LT(fit.after.rms, 3e-4);
  // EC0Y and EXX c1 are separable and recovered.
  for (int j = 0; j < 5; ++j) {
    if (fit.names[j] == "EC0Y") {
      EXPECT_TRUE(fit.statistics.identifiable[j]);
      EXPECT_NEAR(fit.parameters(j), 15e-6, 4.0 * fit.statistics.standardDeviation(j));
    }
  }
}

TEST(MachineIdentification, TwoToolLengthsSeparatePitchAndRecoverWithinThreeSigma) {
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
  const auto [problem, fit] = testing::fitFxyz(options);
  EXPECT_EQ(fit.statistics.rank, 5);
  EXPECT_TRUE(fit.statistics.unidentifiable.empty());
  // Internal units: mm, mm/mm, rad. Order of the template keys (std::map): EBX, EC0Y, EXX, EXZ.
  Eigen::VectorXd truth(5);
  truth << 25e-6, 15e-6, 3e-3, 12e-6, -20e-6;
  ASSERT_EQ(fit.names, (std::vector<std::string>{"EBX", "EC0Y", "EXX c0", "EXX c1", "EXZ c1"}));
  expectWithinSigma(fit, truth, 0);
  // 600 rows - 5 parameters; s0 / sigma has a relative spread of 1 / sqrt(2 * 595) = 3 %.
  const double s0 = std::sqrt(fit.statistics.varianceFactor);
  EXPECT_NEAR(s0, 1e-3, 0.15e-3);
}

TEST(MachineIdentification, MeasuredAnglesSeparatePitchWithOneToolLength) {
  // The angular error of FXYZ with EBX = b is (0, b, 0) whatever the tool: measuring it pins EBX
  // down where one tool length alone could not (see the test above).
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.withAngles = true;
  options.angleNoiseRad = 1e-6;
  const MeasurementSet data = simulate(testing::machineSpec(testing::fxyzTruth()), options);
  const auto problem =
      makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
  EXPECT_EQ(problem->residualsPerObservation(), 6);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 5);
  Eigen::VectorXd truth(5);
  truth << 25e-6, 15e-6, 3e-3, 12e-6, -20e-6;
  expectWithinSigma(fit, truth, 0);
  // Angular rows count 1 mm per mrad (angleScaleMm 1000): 1 urad of noise weighs like 1 um, so
  // s0 stays at the common noise level of 1 um.
  EXPECT_NEAR(std::sqrt(fit.statistics.varianceFactor), 1e-3, 0.15e-3);
}

TEST(MachineIdentification, LinearAndLevenbergMarquardtAgree) {
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
  const MeasurementSet data = simulate(testing::machineSpec(testing::fxyzTruth()), options);
  const auto problem =
      makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
  const FitResult linear = solve(*problem, problem->startVector());
  SolveOptions lm;
  lm.method = Method::LevenbergMarquardt;
  const FitResult nonlinear = solve(*problem, problem->startVector(), lm);
  ASSERT_TRUE(nonlinear.converged) << nonlinear.termination;
  for (int j = 0; j < 5; ++j) {
    // Same minimum: differences far below the statistical uncertainty.
    EXPECT_NEAR(linear.parameters(j), nonlinear.parameters(j),
                1e-3 * linear.statistics.standardDeviation(j))
        << linear.names[j];
    EXPECT_NEAR(linear.statistics.standardDeviation(j), nonlinear.statistics.standardDeviation(j),
                1e-3 * linear.statistics.standardDeviation(j));
  }
}

TEST(MachineIdentification, WeightsScaleTheUncertainty) {
  // Same data, every weight 4: the weighted residuals double, s0 doubles, and sigma (which scales
  // with s0 / sqrt(weight)) stays the same, since the weights are relative.
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250)};
  MeasurementSet data = simulate(testing::machineSpec(testing::fxyzTruth()), options);
  const auto plain =
      makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
  const FitResult a = solve(*plain, plain->startVector());
  for (Measurement& m : data.points) m.weight = 4.0;
  const auto weighted =
      makeIdentificationProblem(testing::templateDocument(testing::fxyzTemplate()), data);
  const FitResult b = solve(*weighted, weighted->startVector());
  EXPECT_NEAR(std::sqrt(b.statistics.varianceFactor), 2.0 * std::sqrt(a.statistics.varianceFactor),
              1e-9);
  for (int j = 0; j < 5; ++j) {
    EXPECT_NEAR(a.parameters(j), b.parameters(j), 1e-9 * std::abs(a.parameters(j)) + 1e-15);
    EXPECT_NEAR(a.statistics.standardDeviation(j), b.statistics.standardDeviation(j),
                1e-9 * a.statistics.standardDeviation(j));
  }
  // The RMS/max statistics are unweighted: the same for both.
  EXPECT_NEAR(a.after.rms, b.after.rms, 1e-12);
}

TEST(MachineIdentification, SquarenessAndStraightnessSlopeAreNamedTogether) {
  // EC0Y = c rotates the Y axis about Z: e_x = -c y to first order, the same as EXY c1 = -c.
  json truth = testing::fxyzTruth();
  json t = truth;
  t["components"] = {
      {"EC0Y", {{"identify", "constant"}}},
      {"EXY", {{"identify", {{"basis", "polynomial"}, {"degree", 2}, {"zero_at", 0}}}}}};
  SyntheticOptions options;
  options.noiseMm = 1e-4;
  const MeasurementSet data = simulate(testing::machineSpec(truth), options);
  const auto problem = makeIdentificationProblem(testing::templateDocument(t), data);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 2);
  ASSERT_EQ(fit.statistics.unidentifiable.size(), 1u);
  EXPECT_EQ(namesOf(fit.statistics.unidentifiable[0], fit),
            (std::set<std::string>{"EC0Y", "EXY c1"}))
      << fit.statistics.unidentifiable[0].description;
  // With min_degree 2 the slope is left to the squareness and everything is identifiable.
  t["components"]["EXY"]["identify"] = {{"basis", "polynomial"}, {"degree", 2}, {"min_degree", 2}};
  const auto separable = makeIdentificationProblem(testing::templateDocument(t), data);
  const FitResult fit2 = solve(*separable, separable->startVector());
  EXPECT_EQ(fit2.statistics.rank, 2);
  EXPECT_TRUE(fit2.statistics.unidentifiable.empty());
}

TEST(MachineIdentification, InstrumentFrameRotationIsRecovered) {
  // The laser tracker's frame is turned by (20, -30, 50) urad and shifted by (10, -20, 5) um.
  json truth = testing::fxyzTruth();
  truth["components"] = {{"EXX", {{"polynomial", {0.0, 0.012}}}},
                         {"EYY", {{"polynomial", {0.0, -0.008}}}},
                         {"EZZ", {{"polynomial", {0.0, 0.005, 1e-5}}}}};
  json t = truth;
  for (const char* name : {"EXX", "EYY", "EZZ"}) {
    t["components"][name] = {
        {"identify", {{"basis", "polynomial"}, {"degree", 2}, {"zero_at", 0}}}};
  }
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.frameRotationRad = Eigen::Vector3d(20e-6, -30e-6, 50e-6);
  options.frameTranslationMm = Eigen::Vector3d(0.010, -0.020, 0.005);
  const MeasurementSet data = simulate(testing::machineSpec(truth), options);
  IdentificationOptions identification;
  identification.instrumentFrame = true;
  const auto problem =
      makeIdentificationProblem(testing::templateDocument(t), data, identification);
  const FitResult fit = solve(*problem, problem->startVector());
  ASSERT_EQ(fit.statistics.parameterCount, 12);
  EXPECT_EQ(fit.statistics.rank, 12);
  // Parameters: EXX c1 c2, EYY c1 c2, EZZ c1 c2, frame rx ry rz tx ty tz (internal units).
  Eigen::VectorXd expected(12);
  expected << 12e-6, 0, -8e-6, 0, 5e-6, 1e-8, 20e-6, -30e-6, 50e-6, 0.010, -0.020, 0.005;
  expectWithinSigma(fit, expected, 0);
  EXPECT_EQ(fit.names[8], "frame rz");
  EXPECT_TRUE(problem->parameterInfo()[8].nuisance);
  // Without the frame parameters the rotation cannot be explained: the fit stays far worse.
  const auto withoutFrame = makeIdentificationProblem(testing::templateDocument(t), data);
  const FitResult rigid = solve(*withoutFrame, withoutFrame->startVector());
  EXPECT_GT(rigid.after.rms, 5.0 * fit.after.rms);
}

// XYFZ vertical machining centre with all 21 components: positioning and straightness as cubic
// polynomials zero at the axis origin (straightness from degree 2, the slope being the
// squareness), angular errors linear and quadratic, three squareness errors.
json vmcTruth() {
  return json{{"format", "volcomp-model/1"},
              {"topology", "XYFZ"},
              {"tool", {0, 0, 100}},
              {"travel", {{"X", {0, 800}}, {"Y", {0, 500}}, {"Z", {-400, 0}}}},
              {"error_units", {{"length", "um"}, {"angle", "urad"}}},
              {"components",
               {{"EXX", {{"polynomial", {0, 0.01, -1e-5, 2e-8}}}},
                {"EYX", {{"polynomial", {0, 0, 2e-5, -1e-8}}}},
                {"EZX", {{"polynomial", {0, 0, -1.5e-5, 1e-8}}}},
                {"EAX", {{"polynomial", {0, 0.01, 1e-5}}}},
                {"EBX", {{"polynomial", {0, -0.02, 2e-5}}}},
                {"ECX", {{"polynomial", {0, 0.015, -1e-5}}}},
                {"EXY", {{"polynomial", {0, 0, 3e-5, -2e-8}}}},
                {"EYY", {{"polynomial", {0, -0.008, 2e-5, 1e-8}}}},
                {"EZY", {{"polynomial", {0, 0, 1e-5, 3e-8}}}},
                {"EAY", {{"polynomial", {0, 0.02, -2e-5}}}},
                {"EBY", {{"polynomial", {0, 0.01, 3e-5}}}},
                {"ECY", {{"polynomial", {0, -0.01, 2e-5}}}},
                {"EXZ", {{"polynomial", {0, 0, 2e-5, 3e-8}}}},
                {"EYZ", {{"polynomial", {0, 0, -2e-5, -2e-8}}}},
                {"EZZ", {{"polynomial", {0, 0.006, 1e-5, 1e-8}}}},
                {"EAZ", {{"polynomial", {0, -0.015, 1e-5}}}},
                {"EBZ", {{"polynomial", {0, 0.02, 1e-5}}}},
                {"ECZ", {{"polynomial", {0, 0.01, -3e-5}}}},
                {"EC0Y", 12.0},
                {"EB0Z", -8.0},
                {"EA0Z", 5.0}}}};
}

json vmcTemplate() {
  json t = vmcTruth();
  for (auto& [name, value] : t["components"].items()) {
    if (name.size() == 4) {
      value = {{"identify", "constant"}};
      continue;
    }
    const bool angle = name[1] == 'A' || name[1] == 'B' || name[1] == 'C';
    const bool positioning = name[1] == name[2];
    json basis = {{"basis", "polynomial"}, {"degree", angle ? 2 : 3}, {"zero_at", 0}};
    if (!angle && !positioning) basis["min_degree"] = 2;
    value = {{"identify", basis}};
  }
  return t;
}

std::vector<Eigen::Vector3d> fourTools() {
  return {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250), Eigen::Vector3d(150, 0, 150),
          Eigen::Vector3d(0, 150, 150)};
}

TEST(MachineIdentification, TwentyOneComponentRoundTripWithFourTools) {
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = fourTools();
  options.seed = 21;
  const model::MachineModelSpec truthSpec = testing::machineSpec(vmcTruth());
  const MeasurementSet data = simulate(truthSpec, options);
  const auto problem = makeIdentificationProblem(testing::templateDocument(vmcTemplate()), data);
  const FitResult fit = solve(*problem, problem->startVector());
  for (const Combination& c : fit.statistics.unidentifiable) ADD_FAILURE() << c.description;
  EXPECT_EQ(fit.statistics.rank, fit.statistics.parameterCount);
  EXPECT_TRUE(fit.converged) << fit.termination;
  // 400 points x 3 rows - 54 parameters = 1146 dof: s0 / sigma spread 2 %.
  EXPECT_NEAR(std::sqrt(fit.statistics.varianceFactor), 1e-3, 0.1e-3);

  // Compare the identified model with the truth where it matters: the predicted errors at
  // points and tools not used for the fit agree to a few noise-sigmas of the fit.
  const model::MachineModel truthModel(truthSpec);
  const auto* machine = dynamic_cast<const IdentificationProblem*>(problem.get());
  ASSERT_NE(machine, nullptr);
  const model::MachineModel fitted(testing::machineSpec(machine->modelJson(fit.parameters)));
  model::Workspace ws;
  double worst = 0.0;
  for (double x : {50.0, 333.0, 777.0}) {
    for (double y : {20.0, 260.0, 480.0}) {
      for (double z : {-380.0, -170.0, -10.0}) {
        const Eigen::Vector3d q(x, y, z), tool(40, -30, 180);
        worst = std::max(worst, (model::evaluate(fitted, ws, q, tool).errorMm -
                                 model::evaluate(truthModel, ws, q, tool).errorMm)
                                    .norm());
      }
    }
  }
  EXPECT_LT(worst, 1.5e-3);

  // Parameters one by one: the true coefficients in the order of the report.
  const model::MachineModelSpec& spec = truthSpec;
  Eigen::VectorXd truth(fit.statistics.parameterCount);
  int j = 0;
  std::map<std::string, int> motionIndex, locationIndex;
  for (int i = 0; i < 18; ++i) motionIndex[model::motionName(i)] = i;
  for (int i = 0; i < 9; ++i) locationIndex[model::locationName(i)] = i;
  for (const ParameterInfo& info : problem->parameterInfo()) {
    const std::string component = info.keyPath.substr(std::string("components.").size());
    if (auto l = locationIndex.find(component); l != locationIndex.end()) {
      truth(j++) = spec.locationRad[static_cast<std::size_t>(l->second)];
      continue;
    }
    const auto& polynomial = std::get<model::PolynomialSpec>(
        spec.motion[static_cast<std::size_t>(motionIndex[component])]);
    const int power = std::stoi(info.name.substr(info.name.find(" c") + 2));
    truth(j++) = polynomial.coefficients[static_cast<std::size_t>(power)];
  }
  expectWithinSigma(fit, truth, 1);
}

TEST(MachineIdentification, BatchJacobianMatchesThePointByPointOne) {
  // jacobian() evaluates whole models on the batch path; ResidualProblem::jacobian() stacks the
  // point-by-point observationJacobian(). Both are finite differences of the same composition:
  // they agree far below the steps' own error. The 21-component template with its location
  // errors, four tools, and a bidirectional table with directions per point.
  SyntheticOptions options;
  options.noiseMm = 1e-3;
  options.tools = fourTools();
  options.directions = {
      {model::Direction::Positive, model::Direction::Negative, model::Direction::Unknown},
      {model::Direction::Negative, model::Direction::Positive, model::Direction::Positive}};
  json t = vmcTemplate();
  t["components"]["EXX"] = {{"identify",
                             {{"basis", "table"},
                              {"positions", {0, 200, 400, 600, 800}},
                              {"interpolation", "cubic"},
                              {"bidirectional", true},
                              {"smoothness", 1e-6}}}};
  const MeasurementSet data = simulate(testing::machineSpec(vmcTruth()), options);
  const auto problem = makeIdentificationProblem(testing::templateDocument(t), data);
  // At a point away from the start, so that the identified functions and location errors are
  // not zero.
  Eigen::VectorXd p = problem->startVector();
  for (Eigen::Index j = 0; j < p.size(); ++j) p(j) = 1e-5 * std::sin(1.0 + static_cast<double>(j));
  Eigen::MatrixXd batch, pointwise;
  problem->jacobian(p, batch);
  problem->ResidualProblem::jacobian(p, pointwise);
  ASSERT_EQ(batch.rows(), pointwise.rows());
  ASSERT_EQ(batch.cols(), pointwise.cols());
  for (Eigen::Index j = 0; j < batch.cols(); ++j) {
    EXPECT_LT((batch.col(j) - pointwise.col(j)).norm(), 1e-7 * pointwise.col(j).norm() + 1e-12)
        << parameterName(*problem, j);
  }
}

TEST(MachineIdentification, TableBasisWithSmoothnessRecoversAPositioningCurve) {
  json truth = testing::fxyzTruth();
  truth["components"] = {{"EXX",
                          {{"positions", {0, 200, 400, 600, 800}},
                           {"values", {0, 4, 7, 9, 14}},
                           {"interpolation", "cubic"}}}};
  json t = truth;
  t["components"]["EXX"] = {{"identify",
                             {{"basis", "table"},
                              {"positions", {0, 200, 400, 600, 800}},
                              {"interpolation", "cubic"},
                              {"smoothness", 1e-6}}}};
  SyntheticOptions options;
  options.noiseMm = 5e-4;
  options.x = {0, 50, 100, 150, 200, 250, 300, 350, 400, 450, 500, 550, 600, 650, 700, 750, 800};
  const MeasurementSet data = simulate(testing::machineSpec(truth), options);
  const auto problem = makeIdentificationProblem(testing::templateDocument(t), data);
  EXPECT_EQ(problem->priorRowCount(), 3);
  const FitResult fit = solve(*problem, problem->startVector());
  EXPECT_EQ(fit.statistics.rank, 5);
  Eigen::VectorXd expected(5);
  expected << 0, 4e-3, 7e-3, 9e-3, 14e-3;
  expectWithinSigma(fit, expected, 0);
  EXPECT_EQ(fit.names[1], "EXX[200]");
  // The written model holds the table in the template's units.
  const json written = problem->modelJson(fit.parameters);
  EXPECT_EQ(written["components"]["EXX"]["interpolation"], "cubic");
  // (um in the file; 4 sigma as above)
  EXPECT_NEAR(written["components"]["EXX"]["values"][2].get<double>(), 7.0,
              4.0 * fit.statistics.standardDeviation(2) * 1000.0);
  EXPECT_NEAR(written["components"]["EXX"]["values"][2].get<double>(), fit.parameters(2) * 1000.0,
              1e-9);
}

}  // namespace
}  // namespace volcomp::calibration
