// Identifiability decided from each parameter's projection onto the null space, the policy for
// what the data cannot see (minimum-norm change from the start values), and prediction
// uncertainty on hand-made linear problems.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {
namespace {

using testing::randomMatrix;

// r(p) = J p - y, one residual per observation.
class LinearProblem final : public ResidualProblem {
 public:
  LinearProblem(Eigen::MatrixXd j, Eigen::VectorXd y) : j_(std::move(j)), y_(std::move(y)) {}
  int parameterCount() const override { return static_cast<int>(j_.cols()); }
  int observationCount() const override { return static_cast<int>(j_.rows()); }
  int residualsPerObservation() const override { return 1; }
  void observationResiduals(const double* p, int i, double* r) const override {
    r[0] = j_.row(i).dot(Eigen::Map<const Eigen::VectorXd>(p, j_.cols())) - y_(i);
  }
  std::string parameterName(int j) const override { return std::string(1, char('a' + j)); }

 private:
  Eigen::MatrixXd j_;
  Eigen::VectorXd y_;
};

// Column d = a + 0.03 b: the direction (a +1, b +0.03, d -1) leaves every residual unchanged.
// b takes part with a small share (below the 0.1 at which a listing would drop it), so its value
// is no more determined than a's or d's.
Eigen::MatrixXd smallShareJacobian() {
  Eigen::MatrixXd jacobian = randomMatrix(60, 4, 11);
  jacobian.col(3) = jacobian.col(0) + 0.03 * jacobian.col(1);
  return jacobian;
}

TEST(Identifiability, ASmallShareMakesAParameterUnidentifiable) {
  const Eigen::MatrixXd jacobian = smallShareJacobian();
  const FitStatistics stats =
      analyse(jacobian, Eigen::VectorXd::Zero(60), {"a", "b", "c", "d"}, 1e-7);
  EXPECT_EQ(stats.rank, 3);
  EXPECT_EQ(stats.identifiable, (std::vector<bool>{false, false, true, false}));
  EXPECT_TRUE(std::isnan(stats.standardDeviation(1))) << "b gets no sigma";
  EXPECT_TRUE(std::isnan(stats.correlation(1, 2)));
  EXPECT_FALSE(std::isnan(stats.standardDeviation(2)));
  // c is orthogonal to the null space up to rounding; b's projection is a real share.
  EXPECT_LT(stats.nullSpaceProjection(2), 1e-12);
  EXPECT_GT(stats.nullSpaceProjection(1), 0.01);
  EXPECT_EQ(stats.identifiabilityThreshold, kIdentifiabilityThreshold);
  ASSERT_EQ(stats.unidentifiable.size(), 1u);
  const Combination& combination = stats.unidentifiable[0];
  ASSERT_EQ(combination.terms.size(), 3u) << combination.description;
  EXPECT_EQ(combination.description.rfind("a, b and d are not separable", 0), 0u)
      << combination.description;
  // In internal units the direction is (1, 0.03, 0, -1) up to the pivot's scale.
  std::map<int, double> raw(combination.rawTerms.begin(), combination.rawTerms.end());
  EXPECT_EQ(raw.at(combination.pivot), 1.0);
  EXPECT_NEAR(raw.at(1) / raw.at(0), 0.03, 1e-9);
  EXPECT_NEAR(raw.at(3) / raw.at(0), -1.0, 1e-9);
  EXPECT_LT(combination.residualChangePerPivotUnit, 1e-12);
  // Why b has no sigma: two parameter vectors that differ in b by 0.03 (and in a, d) explain
  // the data exactly alike.
  const Eigen::Vector4d p(0.5, 1.0, 2.0, -1.0);
  const Eigen::Vector4d q = p + Eigen::Vector4d(1.0, 0.03, 0.0, -1.0);
  EXPECT_LT((jacobian * (q - p)).norm(), 1e-12);
}

TEST(Identifiability, SolutionIsTheMinimumNormChangeFromTheStartValues) {
  const Eigen::MatrixXd jacobian = smallShareJacobian();
  const Eigen::Vector4d truth(0.2, -0.4, 1.5, 0.3);
  const Eigen::VectorXd y = jacobian * truth + 1e-3 * randomMatrix(60, 1, 12).col(0);
  const LinearProblem problem(jacobian, y);
  const Eigen::Vector4d start(5.0, 5.0, 5.0, 5.0);
  for (Method method : {Method::Linear, Method::LevenbergMarquardt}) {
    SCOPED_TRACE(method == Method::Linear ? "linear" : "levenberg-marquardt");
    SolveOptions options;
    options.method = method;
    const FitResult fit = solve(problem, start, options);
    ASSERT_TRUE(fit.converged) << fit.termination;
    // The change from the start, in scaled units, has no component along the null space.
    const Eigen::VectorXd change =
        (fit.parameters - start).cwiseQuotient(fit.statistics.columnScale);
    EXPECT_LT((fit.statistics.nullBasis.transpose() * change).norm(), 1e-8 * change.norm());
    // And the data are fitted: the identifiable c is recovered.
    EXPECT_NEAR(fit.parameters(2), truth(2), 4.0 * fit.statistics.standardDeviation(2));
  }
}

TEST(Identifiability, PredictionsAlongTheNullSpaceAreNotDetermined) {
  const Eigen::MatrixXd jacobian = smallShareJacobian();
  const Eigen::VectorXd residuals = 1e-3 * randomMatrix(60, 1, 13).col(0);
  const FitStatistics stats = analyse(jacobian, residuals, {"a", "b", "c", "d"}, 1e-7);
  // A row like the measured ones: determined, sigma the textbook s0 |g (J^T J)^+ ...|.
  const Eigen::RowVectorXd measured = jacobian.row(7);
  const PredictionUncertainty atData = predictionUncertainty(stats, measured);
  EXPECT_TRUE(atData.determined);
  EXPECT_GT(atData.std, 0.0);
  // b alone changes along the null direction (by 0.03 per unit): not determined. a + d does not
  // (1 - 1 = 0): determined, although neither a nor d is.
  EXPECT_FALSE(functionUncertainty(stats, Eigen::RowVector4d(0, 1, 0, 0)).determined);
  EXPECT_FALSE(functionUncertainty(stats, Eigen::RowVector4d(1, 0, 0, 0)).determined);
  const PredictionUncertainty sum = functionUncertainty(stats, Eigen::RowVector4d(1, 0, 0, 1));
  EXPECT_TRUE(sum.determined);
  EXPECT_LT(sum.nullShare, 1e-12);
  EXPECT_GT(sum.std, 0.0);
  EXPECT_TRUE(functionUncertainty(stats, measured).determined);
  // A quantity that mostly follows the null direction is not determined at any scale.
  const Eigen::RowVectorXd along = Eigen::RowVector4d(1.0, 0.03, 0.0, -1.0) * 1e-6;
  EXPECT_FALSE(functionUncertainty(stats, along).determined);
}

// The example template (config/examples/vmc-xyfz-21-template.json) on the simulator's true
// machine, measured with the cross of four tools over the travel: the squareness EC0Y, the yaw
// table of Y (ECY) and the roll table of Z (ECZ) all turn the tool about Z, and only their sum
// is seen. ECY at 0 takes part with a small share (below 0.1 in units of the sensitivities): a
// listing with a cut-off would leave it out, call it identified and give it the pseudo-inverse's
// sigma, several times smaller than its actual error.
TEST(Identifiability, TheExampleTemplatesRotationsAboutZAreNamedCompletely) {
  const std::string examples = VOLCOMP_EXAMPLES_DIR;
  config::ParseOptions templateOptions;
  templateOptions.allowIdentify = true;
  const config::ModelDocument document =
      config::loadModelFile(examples + "/vmc-xyfz-21-template.json", templateOptions);
  const model::MachineModelSpec truth = std::get<model::MachineModelSpec>(
      config::loadModelFile(examples + "/vmc-xyfz-21-true.json").spec);
  testing::SyntheticOptions options;
  options.x = {0, 85, 170, 255, 340, 425, 510, 595, 680, 765, 850};
  options.y = {0, 50, 100, 150, 200, 250, 300, 350, 400, 450, 500};
  // The end-to-end test's spacing: a straightness c2..c6 together with the linear and constant
  // terms other components carry needs more than 7 positions along its axis, and the tables as
  // many positions as nodes; fewer leave combinations besides the 3 structural ones.
  options.z = {-500, -437.5, -375, -312.5, -250, -187.5, -125, -62.5, 0};
  options.tools = {Eigen::Vector3d(0, 0, 120), Eigen::Vector3d(0, 0, 220),
                   Eigen::Vector3d(100, 0, 120), Eigen::Vector3d(0, 100, 120)};
  options.noiseMm = 5e-4;
  const MeasurementSet data = testing::simulate(truth, options);
  const auto problem = makeIdentificationProblem(document, data);
  const FitResult fit = solve(*problem, problem->startVector());
  const FitStatistics& st = fit.statistics;
  ASSERT_EQ(st.rank, 122);
  const auto index = [&](const std::string& name) {
    const auto it = std::find(fit.names.begin(), fit.names.end(), name);
    EXPECT_NE(it, fit.names.end()) << name;
    return static_cast<Eigen::Index>(it - fit.names.begin());
  };
  const Eigen::Index ecy0 = index("ECY[0]");
  const Combination* aboutZ = nullptr;
  for (const Combination& c : st.unidentifiable) {
    for (const auto& [j, coefficient] : c.terms) {
      if (j == ecy0) aboutZ = &c;
    }
  }
  ASSERT_NE(aboutZ, nullptr) << "ECY[0] must be named";
  double share = 0.0;
  std::set<std::string> names;
  for (const auto& [j, coefficient] : aboutZ->terms) {
    names.insert(fit.names[static_cast<std::size_t>(j)]);
    if (j == ecy0) share = std::abs(coefficient);
  }
  EXPECT_LT(share, 0.1) << "the small share a cut-off would drop";
  EXPECT_TRUE(names.count("EC0Y") && names.count("ECZ[0]") && names.count("ECY[500]"))
      << aboutZ->description;
  EXPECT_FALSE(st.identifiable[static_cast<std::size_t>(ecy0)]);
  EXPECT_TRUE(std::isnan(st.standardDeviation(ecy0)));
  // The combination as listed leaves the residuals unchanged (per unit of the pivot).
  EXPECT_LT(aboutZ->residualChangePerPivotUnit, 1e-9);
  // What a cut-off would have claimed: the pseudo-inverse's sigma for ECY[0], far below how far
  // its value is from the truth (the value along the combination is the policy's, not a
  // measurement).
  const double pseudoSigma = std::sqrt(st.covariance(ecy0, ecy0));
  const double trueValue =
      model::ErrorFunction(truth.motion[static_cast<std::size_t>(
                               model::motionIndex(model::Axis::Y, model::MotionKind::EC))])
          .value(0.0);
  EXPECT_GT(std::abs(fit.parameters(ecy0) - trueValue), 3.0 * pseudoSigma)
      << "fitted " << fit.parameters(ecy0) << ", true " << trueValue << ", pseudo-sigma "
      << pseudoSigma;
  // Identifiable parameters are orthogonal to the null space to rounding.
  for (Eigen::Index j = 0; j < st.nullSpaceProjection.size(); ++j) {
    if (st.identifiable[static_cast<std::size_t>(j)]) {
      EXPECT_LT(st.nullSpaceProjection(j), 1e-9) << fit.names[static_cast<std::size_t>(j)];
    } else {
      EXPECT_GT(st.nullSpaceProjection(j), 1e-3) << fit.names[static_cast<std::size_t>(j)];
    }
  }
}

}  // namespace
}  // namespace volcomp::calibration
