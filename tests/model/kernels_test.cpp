// The per-point code is built twice (baseline and AVX2 + FMA, picked by the CPU at construction):
// on a machine with AVX2 every other test runs the AVX2 build, so this one holds the baseline
// build to it. Both compile the same source, so they may differ by rounding only; 1e-12 mm (and
// rad) is far below anything the model resolves and far above rounding (~1e-16 relative on
// values below 1e3 mm).

#include <random>

#include <gtest/gtest.h>

#include "fast/eval_plan.hpp"
#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

constexpr double kTolerance = 1e-12;

void expectNear(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const char* what) {
  EXPECT_LE((a - b).norm(), kTolerance) << what << ": " << a.transpose() << " vs " << b.transpose();
}

void compareKernels(const MachineModel& model, std::mt19937& rng, double travelMm) {
  const detail::Kernels& generic = detail::genericKernels();
  std::uniform_real_distribution<double> u(-1.2 * travelMm, 1.2 * travelMm);  // some outside
  std::uniform_int_distribution<int> direction(-1, 1);
  Workspace ws, wsGeneric;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const Directions dirs{static_cast<Direction>(direction(rng)),
                          static_cast<Direction>(direction(rng)),
                          static_cast<Direction>(direction(rng))};
    for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
      const PointError e = evaluate(model, ws, q, dirs, mode);
      const PointError g = generic.evaluate(model, wsGeneric, q, model.toolMm(), dirs, mode);
      expectNear(e.errorMm, g.errorMm, "errorMm");
      expectNear(e.angularErrorRad, g.angularErrorRad, "angularErrorRad");
      EXPECT_EQ(e.clampedAxes, g.clampedAxes);
      for (int c = 0; c < 18; ++c) EXPECT_NEAR(ws.motion[c], wsGeneric.motion[c], kTolerance);
      const PointError ce = composeError(model, ws, q, ws.motion, model.toolMm(), mode);
      const PointError cg = generic.compose(model, wsGeneric, q, ws.motion, model.toolMm(), mode);
      expectNear(ce.errorMm, cg.errorMm, "composeError errorMm");
      expectNear(ce.angularErrorRad, cg.angularErrorRad, "composeError angularErrorRad");
    }
    MotionValues values{}, valuesGeneric{};
    EXPECT_EQ(evaluateMotion(model, q, dirs, values),
              generic.motion(model, q, dirs, valuesGeneric));
    for (int c = 0; c < 18; ++c) EXPECT_NEAR(values[c], valuesGeneric[c], kTolerance);
    const OffsetSolution o = solveOffset(model, ws, q, dirs);
    const OffsetSolution og = generic.solve(model, wsGeneric, q, dirs, OffsetOptions{});
    expectNear(o.offsetMm, og.offsetMm, "offsetMm");
    EXPECT_EQ(o.converged, og.converged);
    EXPECT_EQ(o.clampedAxes, og.clampedAxes);
  }
}

TEST(Kernels, BaselineBuildAgreesOnRandomModels) {
  std::mt19937 rng(20261122);
  for (int i = 0; i < 100; ++i) {
    const MachineModel model(testing::randomModel(rng, 1e-3, 500, 400));
    SCOPED_TRACE(model.topology().text());
    compareKernels(model, rng, 500);
  }
}

// Every axis tabulated over one uniform grid (the unrolled lookup), in all 24 topologies, with
// bidirectional X tables, and angles up to 3e-2 rad (above the small-angle series) in one of the
// two models per topology.
TEST(Kernels, BaselineBuildAgreesOnUniformModels) {
  std::mt19937 rng(7);
  for (const std::string& topology : allTopologies()) {
    for (const double maxAngleRad : {1e-3, 3e-2}) {
      MachineModelSpec spec = testing::fullModel(topology, 101, maxAngleRad);
      for (int c = 0; c < 6; ++c) {  // X: bidirectional, the negative curve 1 um / 1 urad off
        TableSpec& table = std::get<TableSpec>(spec.motion[c]);
        for (const double v : table.values)
          table.valuesNegative.push_back(v + (c < 3 ? 1e-3 : 1e-6));
      }
      const MachineModel model(spec);
      SCOPED_TRACE(topology);
      ASSERT_TRUE(detail::PlanAccess::plan(model).allUniform);
      compareKernels(model, rng, 500);
    }
  }
}

}  // namespace
}  // namespace volcomp::model
