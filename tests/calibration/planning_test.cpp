// Measurement planning (volcomp plan) on the example template with the simulator's true machine:
// a planned design of N points reaches the prediction uncertainty of random designs of 4N/3
// points (propagated, and by simulated measurements fitted like a real calibration), the
// I-optimal exchange lowers the mean prediction variance of the D-optimal design, a design the
// planner calls rank deficient is rank deficient in the fit, and one tool offset cannot separate
// what the lever arms of several tools show. (Random designs of 3N points are out of reach for
// this model whatever the criterion: docs/calibration.md gives the bound and the figures.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "random_draws.hpp"
#include "subprocess.hpp"
#include "synthetic.hpp"
#include "volcomp/calibration/planning.hpp"

namespace volcomp::calibration {
namespace {

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

config::ModelDocument exampleTemplate() {
  config::ParseOptions options;
  options.allowIdentify = true;
  return config::loadModelFile(kExamples + "/vmc-xyfz-21-template.json", options);
}

model::MachineModelSpec trueMachine() {
  return std::get<model::MachineModelSpec>(
      config::loadModelFile(kExamples + "/vmc-xyfz-21-true.json").spec);
}

// Candidates: 11 x 11 x 9 positions over the travel with the four tools of the end-to-end test
// (fewer positions along Y or Z leave a straightness polynomial, c2..c6 beside the linear and
// constant terms of other components, with a combination no design can separate).
std::vector<PlanCandidate> candidates(const config::ModelDocument& document) {
  return gridCandidates(std::get<model::MachineModelSpec>(document.spec), {11, 11, 9},
                        {Eigen::Vector3d(0, 0, 120), Eigen::Vector3d(0, 0, 220),
                         Eigen::Vector3d(100, 0, 120), Eigen::Vector3d(0, 100, 120)});
}

std::vector<std::size_t> randomDesign(std::size_t count, std::size_t points, unsigned seed) {
  std::vector<std::size_t> all(count);
  std::iota(all.begin(), all.end(), 0);
  std::mt19937 generator(seed);
  std::shuffle(all.begin(), all.end(), generator);
  all.resize(points);
  return all;
}

// Measures the true machine at the design's points with Gaussian noise, fits the template, and
// returns the RMS over the candidates of |predicted - true| (mm).
double simulatedPredictionError(const config::ModelDocument& document,
                                const std::vector<PlanCandidate>& all,
                                const std::vector<std::size_t>& design, double noiseMm,
                                unsigned seed) {
  const model::MachineModel truth(trueMachine());
  model::Workspace ws;
  std::mt19937 generator(seed);
  std::normal_distribution<double> noise(0.0, noiseMm);
  MeasurementSet measured = designMeasurements(all, design);
  for (Measurement& m : measured.points) {
    m.errorMm =
        model::evaluate(truth, ws, m.qMm, m.toolMm).errorMm + testutil::draw3(noise, generator);
  }
  const auto problem = makeIdentificationProblem(document, measured);
  const FitResult fit = solve(*problem, problem->startVector());
  const model::MachineModel fitted(std::get<model::MachineModelSpec>(
      config::parseModel(problem->modelJson(fit.parameters), "fitted.json").spec));
  double sum = 0.0;
  for (const PlanCandidate& c : all) {
    const Eigen::Vector3d difference = model::evaluate(fitted, ws, c.qMm, c.toolMm).errorMm -
                                       model::evaluate(truth, ws, c.qMm, c.toolMm).errorMm;
    sum += difference.squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(all.size()));
}

TEST(Planning, PlannedNPointsReachRandomFourThirdsNPointsAndIOptimalLowersTheMean) {
  const config::ModelDocument document = exampleTemplate();
  const std::vector<PlanCandidate> all = candidates(document);
  PlanOptions options;
  options.points = 60;
  options.noiseMm = 1e-3;
  options.criterion = PlanCriterion::D;
  const PlanResult dOptimal = planMeasurements(document, all, options);
  options.criterion = PlanCriterion::I;
  const PlanResult iOptimal = planMeasurements(document, all, options);
  EXPECT_EQ(iOptimal.criterion, PlanCriterion::I);
  for (const PlanResult* planned : {&dOptimal, &iOptimal}) {
    ASSERT_EQ(planned->selected.size(), 60u);
    EXPECT_EQ(std::set<std::size_t>(planned->selected.begin(), planned->selected.end()).size(),
              60u);
    // The example template has 3 structural combinations (rank 122 of 125 whatever is measured).
    EXPECT_EQ(planned->candidateRank, 122);
    EXPECT_EQ(planned->statistics.rank, 122);
    EXPECT_EQ(planned->undetermined, 0);
  }
  // What the I criterion minimises: the mean prediction variance over the candidates.
  EXPECT_LT(iOptimal.rmsStdMm, dOptimal.rmsStdMm);

  // Propagated: the largest and the RMS sigma over the candidates of either planned design of 60
  // points are no worse than those of each of five random designs of 80 points.
  double simulatedRandom = 0.0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const PlanResult random =
        evaluateDesign(document, all, randomDesign(all.size(), 80, seed), options);
    for (const PlanResult* planned : {&dOptimal, &iOptimal}) {
      EXPECT_LE(planned->maxStdMm, random.maxStdMm) << "random design " << seed;
      EXPECT_LE(planned->rmsStdMm, random.rmsStdMm) << "random design " << seed;
    }
    simulatedRandom +=
        simulatedPredictionError(document, all, random.selected, options.noiseMm, seed) / 5.0;
  }
  // Simulated: the prediction error of the fitted model against the true machine, averaged over
  // five noise realisations, is no worse for the I-optimal design than for the random ones.
  double simulatedPlanned = 0.0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    simulatedPlanned +=
        simulatedPredictionError(document, all, iOptimal.selected, options.noiseMm, 100 + seed) /
        5.0;
  }
  EXPECT_LE(simulatedPlanned, simulatedRandom);
  // And the propagated sigma describes the simulated error (RMS over the candidates), up to what
  // the template's tables cannot follow of the true curves.
  EXPECT_NEAR(simulatedPlanned, iOptimal.rmsStdMm, 0.3 * iOptimal.rmsStdMm);
}

TEST(Planning, ADesignThePlannerCallsRankDeficientIsRankDeficientInTheFit) {
  const config::ModelDocument document = exampleTemplate();
  const std::vector<PlanCandidate> all = candidates(document);
  for (const auto& [points, criterion] :
       {std::pair{25, PlanCriterion::D}, std::pair{60, PlanCriterion::D},
        std::pair{25, PlanCriterion::I}, std::pair{60, PlanCriterion::I}}) {
    SCOPED_TRACE(::testing::Message()
                 << points << " points, criterion " << (criterion == PlanCriterion::I ? "I" : "D"));
    PlanOptions options;
    options.points = points;
    options.criterion = criterion;
    const PlanResult plan = planMeasurements(document, all, options);
    const bool deficient = plan.statistics.rank < plan.candidateRank;
    EXPECT_EQ(deficient, points == 25) << "25 points give 75 equations for 122 identifiable";
    // The fit of (noise-free) measurements at the planned points: the same rank and the same
    // parameters named as not identifiable.
    MeasurementSet measured = designMeasurements(all, plan.selected);
    const model::MachineModel truth(trueMachine());
    model::Workspace ws;
    for (Measurement& m : measured.points) {
      m.errorMm = model::evaluate(truth, ws, m.qMm, m.toolMm).errorMm;
    }
    const auto problem = makeIdentificationProblem(document, measured);
    const FitResult fit = solve(*problem, problem->startVector());
    EXPECT_EQ(fit.statistics.rank, plan.statistics.rank);
    EXPECT_EQ(fit.statistics.identifiable, plan.statistics.identifiable);
  }
}

TEST(Planning, OneToolCannotSeparateWhatTheToolsLeverArmsShow) {
  // Candidates with one tool: the rank all candidates reach is lower than with the cross of
  // tools, and the planner names what stays unidentifiable before anyone measures.
  const config::ModelDocument document = exampleTemplate();
  const std::vector<PlanCandidate> oneTool = gridCandidates(
      std::get<model::MachineModelSpec>(document.spec), {9, 6, 5}, {Eigen::Vector3d(0, 0, 120)});
  PlanOptions options;
  options.points = 60;
  const PlanResult plan = planMeasurements(document, oneTool, options);
  EXPECT_LT(plan.candidateRank, 122);
  EXPECT_EQ(plan.statistics.rank, plan.candidateRank);
  EXPECT_GT(plan.statistics.unidentifiable.size(), 3u);
}

TEST(Planning, SmoothnessRowsAreInformationOfEveryDesignNotCandidates) {
  // A table with smoothness adds prior rows below the candidates' rows in the sensitivity matrix:
  // both criteria choose among the candidates only, and the prior counts for every design.
  config::ParseOptions parse;
  parse.allowIdentify = true;
  nlohmann::json text =
      nlohmann::json::parse(testutil::readTextFile(kExamples + "/vmc-xyfz-21-template.json"));
  text["components"]["EXX"]["identify"]["smoothness"] = 1e4;
  const config::ModelDocument document = config::parseModel(text, "smooth.json", parse);
  const std::vector<PlanCandidate> all = gridCandidates(
      std::get<model::MachineModelSpec>(document.spec), {9, 6, 5}, {Eigen::Vector3d(0, 0, 120)});
  for (PlanCriterion criterion : {PlanCriterion::D, PlanCriterion::I}) {
    PlanOptions options;
    options.points = 60;
    options.criterion = criterion;
    const PlanResult plan = planMeasurements(document, all, options);
    ASSERT_EQ(plan.selected.size(), 60u);
    EXPECT_EQ(std::set<std::size_t>(plan.selected.begin(), plan.selected.end()).size(), 60u);
    for (std::size_t i : plan.selected) EXPECT_LT(i, all.size());
    EXPECT_EQ(plan.statistics.rank, plan.candidateRank);
  }
}

}  // namespace
}  // namespace volcomp::calibration
