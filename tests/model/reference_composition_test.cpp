// The fast paths (evaluate, evaluateBatch, evaluateMotion, solveOffset, solveOffsetBatch: the
// table plan, the deviation form, the angle series, the SIMD lanes) against the reference
// composition of composition.hpp (one 4x4 transform per carriage, multiplied as the model file
// format writes it), on random models with every component kind and grids, in all 24
// topologies, with small and large angles. The reference itself is held to the worked examples
// and the hand derivations (machine_model_test, components_test).

#include "volcomp/model/composition.hpp"

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

// The reference forms p - p0 from points of ~1e3 mm: its E carries their rounding, a few 1e-13.
constexpr double kPositionToleranceMm = 1e-11;
constexpr double kAngleToleranceRad = 1e-14;

std::vector<Eigen::Vector3d> randomPoints(std::mt19937& rng, int count, double rangeMm) {
  std::uniform_real_distribution<double> u(-rangeMm, rangeMm);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < count; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

// evaluate() (both modes), evaluateBatch() and evaluateMotion() at `points` against the reference.
void compareWithReference(const MachineModel& model, const std::vector<Eigen::Vector3d>& points,
                          const char* what) {
  Workspace ws;
  std::vector<PointError> batch(points.size());
  evaluateBatch(model, ws, points, batch);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(::testing::Message()
                 << what << ", " << model.topology().text() << ", q = " << points[i].transpose());
    const PointError reference = evaluateReference(model, points[i]);
    const PointError exact = evaluate(model, ws, points[i]);
    EXPECT_LT((exact.errorMm - reference.errorMm).norm(), kPositionToleranceMm);
    EXPECT_LT((exact.angularErrorRad - reference.angularErrorRad).norm(), kAngleToleranceRad);
    EXPECT_EQ(exact.clampedAxes, reference.clampedAxes);
    EXPECT_LT((batch[i].errorMm - reference.errorMm).norm(), kPositionToleranceMm);
    EXPECT_LT((batch[i].angularErrorRad - reference.angularErrorRad).norm(), kAngleToleranceRad);
    EXPECT_EQ(batch[i].clampedAxes, reference.clampedAxes);

    MotionValues fast{}, literal{};
    EXPECT_EQ(evaluateMotion(model, points[i], {}, fast),
              referenceMotion(model, points[i], {}, literal));
    for (int c = 0; c < 18; ++c) EXPECT_NEAR(fast[c], literal[c], 1e-15) << motionName(c);
  }
}

TEST(ReferenceComposition, FastPathsAgreeOnRandomModelsWithSmallAndLargeAngles) {
  std::mt19937 rng(4242);
  for (const double maxAngleRad : {1e-4, 1e-3, 2e-2, 0.3}) {
    for (int m = 0; m < 60; ++m) {
      const MachineModel model(testing::randomModel(rng, maxAngleRad, 400, 300));
      compareWithReference(model, randomPoints(rng, 10, 480), "random model");
    }
  }
}

// Every axis tabulated over one uniform grid (the lookup across lanes), all 24 topologies, with
// angles in the short series, the long one and beyond both.
TEST(ReferenceComposition, FastPathsAgreeInEveryTopology) {
  std::mt19937 rng(99);
  for (const std::string& topology : allTopologies()) {
    for (const double maxAngleRad : {1e-3, 5e-3, 3e-2}) {
      const MachineModel model(testing::fullModel(topology, 101, maxAngleRad));
      compareWithReference(model, randomPoints(rng, 9, 600), "full model");
    }
  }
}

// The spec's accuracy of the fast mode: FirstOrder's position within 1e-6 mm of the reference for
// errors of realistic size (angles below 1e-3 rad, arms below 2 m).
TEST(ReferenceComposition, FirstOrderPositionWithinAMicronThousandth) {
  std::mt19937 rng(31);
  for (int m = 0; m < 100; ++m) {
    const MachineModel model(testing::randomModel(rng, 1e-3, 500, 400));
    Workspace ws;
    for (const Eigen::Vector3d& q : randomPoints(rng, 10, 500)) {
      const PointError reference = evaluateReference(model, q);
      const PointError first = evaluate(model, ws, q, {}, EvalMode::FirstOrder);
      ASSERT_LE((first.errorMm - reference.errorMm).norm(), 1e-6)
          << model.topology().text() << " q = " << q.transpose();
    }
  }
}

// Both offset solves put the tool on the nominal point as the reference computes it:
// p(q + o) - p0(q) = E_ref(q + o) + o below the solve's tolerance (plus the reference's rounding).
TEST(ReferenceComposition, OffsetsReachTheNominalPoint) {
  std::mt19937 rng(57);
  for (int m = 0; m < 40; ++m) {
    const MachineModel model(testing::randomModel(rng, 1e-3, 500, 300));
    const std::vector<Eigen::Vector3d> points = randomPoints(rng, 9, 500);
    std::vector<OffsetSolution> batch(points.size());
    Workspace ws;
    solveOffsetBatch(model, ws, points, batch);
    for (std::size_t i = 0; i < points.size(); ++i) {
      SCOPED_TRACE(::testing::Message()
                   << model.topology().text() << ", q = " << points[i].transpose());
      const OffsetSolution single = solveOffset(model, ws, points[i]);
      for (const OffsetSolution& o : {single, batch[i]}) {
        ASSERT_TRUE(o.converged);
        const PointError at = evaluateReference(model, points[i] + o.offsetMm);
        EXPECT_LT((at.errorMm + o.offsetMm).norm(), 1e-9 + kPositionToleranceMm);
      }
    }
  }
}

// The poses themselves: frameMworkpiece and frameMtool are the products the header writes, and
// workpieceMtool maps the tool tip onto p(q).
TEST(ReferenceComposition, PosesComposeAsWritten) {
  const MachineModel model(testing::fullModel("XYFZ", 101, 1e-3));
  const Eigen::Vector3d q(300, 200, -100);
  MotionValues values{};
  referenceMotion(model, q, {}, values);
  const ChainPoses poses = composeChain(model, q, values, model.toolMm());
  // XYFZ: H_FW = C_Y C_X Trans(w), H_FT = C_Z Trans(t).
  Eigen::Isometry3d w = Eigen::Isometry3d::Identity(), t = Eigen::Isometry3d::Identity();
  w.translation() = model.workpieceMm();
  t.translation() = model.toolMm();
  const Eigen::Isometry3d frameMworkpiece =
      parentMcarriage(model, Axis::Y, q, values) * parentMcarriage(model, Axis::X, q, values) * w;
  const Eigen::Isometry3d frameMtool = parentMcarriage(model, Axis::Z, q, values) * t;
  EXPECT_TRUE(poses.frameMworkpiece.isApprox(frameMworkpiece, 1e-15));
  EXPECT_TRUE(poses.frameMtool.isApprox(frameMtool, 1e-15));
  const Eigen::Vector3d toolInWorkpiece =
      poses.frameMworkpiece.inverse() * (poses.frameMtool * Eigen::Vector3d::Zero());
  EXPECT_LT((toolInWorkpiece - poses.workpieceMtool.translation()).norm(), 1e-12);
  // The workpiece-side carriages move opposite to the command: C_X's translation is about -x.
  EXPECT_NEAR(parentMcarriage(model, Axis::X, q, values).translation().x(), -300, 0.1);
  EXPECT_NEAR(parentMcarriage(model, Axis::Z, q, values).translation().z(), -100, 0.1);
}

}  // namespace
}  // namespace volcomp::model
