// Measurement planning (volcomp plan) on the example template: a design the planner calls rank
// deficient is rank deficient in the fit, and one tool offset cannot separate what the lever arms
// of several tools show. (A planned design of N points does not yet reach the prediction
// uncertainty of random designs of 3N points: docs/calibration.md gives the figures.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

TEST(Planning, ADesignThePlannerCallsRankDeficientIsRankDeficientInTheFit) {
  const config::ModelDocument document = exampleTemplate();
  const std::vector<PlanCandidate> all = candidates(document);
  for (int points : {25, 60}) {
    SCOPED_TRACE(points);
    PlanOptions options;
    options.points = points;
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

}  // namespace
}  // namespace volcomp::calibration
