// Property tests on random realistic models (all 24 topologies, components of every kind,
// angles up to 1e-3 rad, lever arms below 2 m).

#include <random>

#include <gtest/gtest.h>

#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

// Travel +-500 mm per axis and tool/workpiece offsets up to 400 mm per component keep every lever
// arm below sqrt(3) * 900 mm < 1.6 m.
constexpr double kTravel = 500;
constexpr double kOffset = 400;

TEST(ExactVsFirstOrder, AgreeWithinMicronThousandthOnRandomModels) {
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> u(-kTravel, kTravel);
  double worst = 0;
  for (int model_i = 0; model_i < 200; ++model_i) {
    const MachineModel model(testing::randomModel(rng, 1e-3, kTravel, kOffset));
    Workspace ws;
    for (int i = 0; i < 50; ++i) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      const PointError exact = evaluate(model, ws, q, {}, EvalMode::Exact);
      const PointError first = evaluate(model, ws, q, {}, EvalMode::FirstOrder);
      const double diff = (exact.errorMm - first.errorMm).norm();
      worst = std::max(worst, diff);
      ASSERT_LE(diff, 1e-6) << model.topology().text() << " q = " << q.transpose();
      // Angular error: first order, O(theta^2) with three carriages of up to 1.7e-3 rad.
      EXPECT_LE((exact.angularErrorRad - first.angularErrorRad).norm(), 2e-5);
    }
  }
  RecordProperty("worst_difference_mm", std::to_string(worst));
}

TEST(ExactVsFirstOrder, WorstCaseAnglesAndArms) {
  // Every angle at +-1e-3 rad with 1-2 m arms: where a second-order expansion of the rotations
  // misses by up to 7e-6 mm (third-order terms); FirstOrder must still agree to 1e-6 mm.
  for (const std::string& topology : allTopologies()) {
    for (const double sign : {1.0, -1.0}) {
      MachineModelSpec spec;
      spec.topology = topology;
      for (int k = 0; k < 3; ++k) {
        for (int kind = 3; kind < 6; ++kind) spec.motion[k * 6 + kind] = sign * 1e-3;
      }
      spec.toolMm = Eigen::Vector3d(0, 0, 1000);
      const MachineModel model(spec);
      Workspace ws;
      const Eigen::Vector3d q(1000, -1000, 1000);
      const PointError exact = evaluate(model, ws, q, {}, EvalMode::Exact);
      const PointError first = evaluate(model, ws, q, {}, EvalMode::FirstOrder);
      EXPECT_LE((exact.errorMm - first.errorMm).norm(), 1e-6) << topology;
    }
  }
}

TEST(OffsetSolve, ReachesNominalPointOnRandomModels) {
  // p(q + o) = p0(q), i.e. E(q + o) + o = 0, to 1e-9 mm, in both modes.
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-kTravel, kTravel);
  for (int model_i = 0; model_i < 100; ++model_i) {
    const MachineModel model(testing::randomModel(rng, 1e-3, kTravel, kOffset));
    Workspace ws;
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
        OffsetOptions options;
        options.mode = mode;
        const OffsetSolution o = solveOffset(model, ws, q, {}, options);
        ASSERT_TRUE(o.converged) << model.topology().text();
        EXPECT_LE(o.residualMm, 1e-9);
        EXPECT_LE(o.iterations, 6);
        const PointError at = evaluate(model, ws, q + o.offsetMm, {}, mode);
        EXPECT_LE((at.errorMm + o.offsetMm).norm(), 1e-9);
        // First order the offset is -E(q); they differ by about the slope of E (here up to
        // ~5e-3: angle slopes of 3e-6 rad/mm on arms of 1.5 m) times |E|.
        const PointError e = evaluate(model, ws, q, {}, mode);
        EXPECT_LE((o.offsetMm + e.errorMm).norm(), 1e-2 * e.errorMm.norm());
      }
    }
  }
}

TEST(OffsetSolve, FullModelEveryTopology) {
  for (const std::string& topology : allTopologies()) {
    const MachineModel model(testing::fullModel(topology));
    Workspace ws;
    for (double s = 0.05; s < 1; s += 0.1) {
      const Eigen::Vector3d q(850 * s, 500 * (1 - s), -500 * s);
      const OffsetSolution o = solveOffset(model, ws, q);
      ASSERT_TRUE(o.converged) << topology;
      const PointError at = evaluate(model, ws, q + o.offsetMm);
      EXPECT_LE((at.errorMm + o.offsetMm).norm(), 1e-9) << topology;
    }
  }
}

}  // namespace
}  // namespace volcomp::model
