// evaluateBatch and solveOffsetBatch compose four points side by side in SIMD lanes, with their
// own table lookup and their own paths for large angles and non-finite values, so each of their
// results is held to evaluate() / solveOffset() of the same point. Both follow the same formulas
// and may differ by rounding only: 1e-12 mm (and rad) is far below anything the model resolves and
// far above rounding (~1e-16 relative on values below 1e3 mm).

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "fast/eval_plan.hpp"
#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

constexpr double kTolerance = 1e-12;

// Equal within kTolerance, or NaN in both.
void expectSame(const Eigen::Vector3d& batch, const Eigen::Vector3d& single, const char* what) {
  for (int c = 0; c < 3; ++c) {
    if (std::isnan(single[c])) {
      EXPECT_TRUE(std::isnan(batch[c])) << what << "[" << c << "]: " << batch[c];
    } else {
      EXPECT_NEAR(batch[c], single[c], kTolerance) << what << "[" << c << "]";
    }
  }
}

void expectSameMotion(const MotionValues& batch, const MotionValues& single) {
  for (int c = 0; c < 18; ++c) {
    if (std::isnan(single[c])) {
      EXPECT_TRUE(std::isnan(batch[c])) << "motion " << c;
    } else {
      EXPECT_NEAR(batch[c], single[c], kTolerance) << "motion " << c;
    }
  }
}

Directions randomDirections(std::mt19937& rng) {
  std::uniform_int_distribution<int> d(-1, 1);
  return {static_cast<Direction>(d(rng)), static_cast<Direction>(d(rng)),
          static_cast<Direction>(d(rng))};
}

// Points over 1.2 times the travel, so that some are clamped.
std::vector<Eigen::Vector3d> randomPoints(std::mt19937& rng, std::size_t count, double travelMm) {
  std::uniform_real_distribution<double> u(-1.2 * travelMm, 1.2 * travelMm);
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < count; ++i) points.emplace_back(u(rng), u(rng), u(rng));
  return points;
}

// evaluateBatch over `points` (with `directions`, possibly fewer) against evaluate() of each.
void compareWithEvaluate(const MachineModel& model, const std::vector<Eigen::Vector3d>& points,
                         const std::vector<Directions>& directions, EvalMode mode) {
  Workspace ws, single;
  std::vector<PointError> out(points.size());
  evaluateBatch(model, ws, points, out, mode, directions);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(::testing::Message()
                 << "point " << i << " of " << points.size() << ": " << points[i].transpose());
    const Directions dirs = i < directions.size() ? directions[i] : Directions{};
    const PointError expected = evaluate(model, single, points[i], dirs, mode);
    expectSame(out[i].errorMm, expected.errorMm, "errorMm");
    expectSame(out[i].angularErrorRad, expected.angularErrorRad, "angularErrorRad");
    EXPECT_EQ(out[i].clampedAxes, expected.clampedAxes);
  }
  // ws.motion holds the last point's motion values, as after evaluate().
  if (!points.empty()) expectSameMotion(ws.motion, single.motion);
}

// solveOffsetBatch over `points` against solveOffset() of each: the same offset (1e-12 mm), the
// same outcome (converged, iterations, clamped axes) and residual (1e-12 mm).
void compareWithSolveOffset(const MachineModel& model, const std::vector<Eigen::Vector3d>& points,
                            const std::vector<Directions>& directions,
                            const OffsetOptions& options = {}) {
  Workspace ws, single;
  std::vector<OffsetSolution> out(points.size());
  solveOffsetBatch(model, ws, points, out, directions, options);
  for (std::size_t i = 0; i < points.size(); ++i) {
    SCOPED_TRACE(::testing::Message()
                 << "point " << i << " of " << points.size() << ": " << points[i].transpose());
    const Directions dirs = i < directions.size() ? directions[i] : Directions{};
    const OffsetSolution expected = solveOffset(model, single, points[i], dirs, options);
    expectSame(out[i].offsetMm, expected.offsetMm, "offsetMm");
    EXPECT_EQ(out[i].converged, expected.converged);
    EXPECT_EQ(out[i].iterations, expected.iterations);
    EXPECT_EQ(out[i].clampedAxes, expected.clampedAxes);
    if (std::isfinite(expected.residualMm)) {
      EXPECT_NEAR(out[i].residualMm, expected.residualMm, kTolerance);
    } else {
      EXPECT_FALSE(std::isfinite(out[i].residualMm));
    }
  }
  // ws.motion holds the last point's motion values at its last evaluated position.
  if (!points.empty()) expectSameMotion(ws.motion, single.motion);
}

// Every size from an empty batch through several blocks, with and without directions, with
// directions for only part of the points, in both modes.
void compareSizes(const MachineModel& model, std::mt19937& rng, double travelMm) {
  for (const std::size_t count : {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 13, 37}) {
    const std::vector<Eigen::Vector3d> points = randomPoints(rng, count, travelMm);
    std::vector<Directions> directions;
    for (std::size_t i = 0; i < count; ++i) directions.push_back(randomDirections(rng));
    const std::vector<Directions> some(directions.begin(),
                                       directions.begin() + static_cast<long>(count / 2));
    for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
      compareWithEvaluate(model, points, {}, mode);
      compareWithEvaluate(model, points, directions, mode);
      compareWithEvaluate(model, points, some, mode);
    }
    compareWithSolveOffset(model, points, {});
    compareWithSolveOffset(model, points, directions);
    compareWithSolveOffset(model, points, some);
  }
}

// Random topologies with components of every kind (non-uniform tables, polynomials, constants,
// grids): the lookup point by point, the composition across lanes.
TEST(Batch, AgreesWithEvaluateOnRandomModels) {
  std::mt19937 rng(20261122);
  for (int i = 0; i < 40; ++i) {
    const MachineModel model(testing::randomModel(rng, 1e-3, 500, 400));
    SCOPED_TRACE(model.topology().text());
    compareSizes(model, rng, 500);
  }
}

// Every axis tabulated over one uniform grid (the lookup across lanes), in all 24 topologies,
// with bidirectional X tables, and angles up to 1e-3 rad (the short series), 5e-3 rad (the long
// one) and 3e-2 rad (beyond both: point by point).
TEST(Batch, AgreesWithEvaluateOnUniformModelsInEveryTopology) {
  std::mt19937 rng(7);
  for (const std::string& topology : allTopologies()) {
    for (const double maxAngleRad : {1e-3, 5e-3, 3e-2}) {
      MachineModelSpec spec = testing::fullModel(topology, 101, maxAngleRad);
      for (int c = 0; c < 6; ++c) {  // X: bidirectional, the negative curve 1 um / 1 urad off
        TableSpec& table = std::get<TableSpec>(spec.motion[c]);
        for (const double v : table.values) {
          table.valuesNegative.push_back(v + (c < 3 ? 1e-3 : 1e-6));
        }
      }
      const MachineModel model(spec);
      SCOPED_TRACE(::testing::Message() << topology << ", angles up to " << maxAngleRad);
      ASSERT_TRUE(detail::PlanAccess::plan(model).allUniform);
      compareSizes(model, rng, 500);
    }
  }
}

// Every error angle 1e-2 rad or below but a rotation of ~1.4e-2 rad in total: the position from
// the lanes, the log map for that point from evaluate()'s general branch.
TEST(Batch, LargeTotalRotationTakesThePointPathForTheAngle) {
  MachineModelSpec spec;
  spec.topology = "FXYZ";
  for (int k = 0; k < 3; ++k) {
    spec.motion[motionIndex(static_cast<Axis>(k), MotionKind::EA)] = 3.3e-3;
    spec.motion[motionIndex(static_cast<Axis>(k), MotionKind::EB)] = 3.3e-3;
  }
  const MachineModel model(spec);
  std::mt19937 rng(3);
  const std::vector<Eigen::Vector3d> points = randomPoints(rng, 9, 300);
  compareWithEvaluate(model, points, {}, EvalMode::Exact);
  compareWithEvaluate(model, points, {}, EvalMode::FirstOrder);
}

// The lanes take sin and cos - 1 from series: up to x^5 below 1e-3 rad, up to x^7 below 1e-2 rad.
// One error angle just below each limit on a 2 m arm (E of 2 mm and 20 mm), held to 1e-15 of E,
// a few times its rounding: the short series without its x^5/120 term (8e-18 rad at 1e-3 rad,
// 1.7e-14 mm here) fails this; the long series' last term (x^7/5040, 2e-18 rad at 1e-2 rad) is
// itself at the rounding of E, so there the test holds the agreement only.
TEST(Batch, AngleSeriesAgreeToRoundingNearTheirLimits) {
  std::mt19937 rng(19);
  for (const char* topology : {"FXYZ", "XYFZ"}) {
    for (int slot = 0; slot < 9; ++slot) {
      for (const double angleRad : {9.9e-4, 9.9e-3}) {
        MachineModelSpec spec;
        spec.topology = topology;
        spec.toolMm = Eigen::Vector3d(0, 0, 2000);
        spec.motion[motionIndex(static_cast<Axis>(slot / 3),
                                static_cast<MotionKind>(3 + slot % 3))] = angleRad;
        const MachineModel model(spec);
        const std::vector<Eigen::Vector3d> points = randomPoints(rng, 8, 1000);
        std::vector<PointError> out(points.size());
        Workspace ws, single;
        evaluateBatch(model, ws, points, out);
        for (std::size_t i = 0; i < points.size(); ++i) {
          const PointError expected = evaluate(model, single, points[i]);
          const double scale = expected.errorMm.norm();
          EXPECT_LE((out[i].errorMm - expected.errorMm).norm(), 1e-15 * scale)
              << topology << ", angle " << slot << " = " << angleRad << ", E "
              << expected.errorMm.transpose();
          EXPECT_LE((out[i].angularErrorRad - expected.angularErrorRad).norm(), 1e-15 * angleRad);
        }
      }
    }
  }
}

// NaN and infinite positions anywhere in a block: that block point by point, the same results
// (NaN where evaluate() gives NaN), and the other blocks unaffected.
TEST(Batch, NonFinitePositionsGiveWhatEvaluateGives) {
  const MachineModel model(testing::fullModel("XYFZ"));
  std::mt19937 rng(11);
  std::vector<Eigen::Vector3d> points = randomPoints(rng, 12, 400);
  points[1].x() = std::numeric_limits<double>::quiet_NaN();
  points[6].z() = std::numeric_limits<double>::infinity();
  points[11].y() = -std::numeric_limits<double>::infinity();
  for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
    compareWithEvaluate(model, points, {}, mode);
  }
}

// The offset solve's stopping rules per lane: an iteration limit that stops some points before
// they converge (and none at all), a tolerance that none reaches, NaN and infinite positions in
// a block beside finite ones.
TEST(Batch, SolveOffsetStopsEachPointAsSolveOffsetDoes) {
  const MachineModel model(testing::fullModel("XYFZ", 101, 3e-3));
  std::mt19937 rng(23);
  std::vector<Eigen::Vector3d> points = randomPoints(rng, 11, 400);
  for (const int maxIterations : {0, 1, 2, 3, 50}) {
    OffsetOptions options;
    options.maxIterations = maxIterations;
    SCOPED_TRACE(::testing::Message() << "maxIterations " << maxIterations);
    compareWithSolveOffset(model, points, {}, options);
  }
  OffsetOptions unreachable;
  unreachable.toleranceMm = 0.0;
  unreachable.maxIterations = 6;
  compareWithSolveOffset(model, points, {}, unreachable);
  points[2].x() = std::numeric_limits<double>::quiet_NaN();
  points[5].y() = std::numeric_limits<double>::infinity();
  compareWithSolveOffset(model, points, {});
  Workspace ws;
  std::vector<OffsetSolution> out(points.size());
  solveOffsetBatch(model, ws, points, out);
  EXPECT_FALSE(out[2].converged);
  EXPECT_FALSE(out[5].converged);
  EXPECT_TRUE(out[3].converged);
}

// The offsets put the tool on the nominal point: p(q + o) - p0(q) = E(q + o) + o below the
// tolerance, checked with evaluate() at q + o.
TEST(Batch, SolveOffsetReachesTheNominalPoint) {
  std::mt19937 rng(29);
  for (const char* topology : {"XYFZ", "FXYZ", "ZFXY"}) {
    const MachineModel model(testing::fullModel(topology, 101, 1e-3));
    const std::vector<Eigen::Vector3d> points = randomPoints(rng, 50, 400);
    std::vector<OffsetSolution> out(points.size());
    Workspace ws;
    solveOffsetBatch(model, ws, points, out);
    for (std::size_t i = 0; i < points.size(); ++i) {
      ASSERT_TRUE(out[i].converged) << topology << " point " << i;
      const PointError at = evaluate(model, ws, points[i] + out[i].offsetMm);
      EXPECT_LT((at.errorMm + out[i].offsetMm).norm(), 1e-9) << topology << " point " << i;
    }
  }
}

// An output shorter than the input: only what fits is evaluated.
TEST(Batch, EvaluatesAsManyPointsAsTheOutputHolds) {
  const MachineModel model(testing::fullModel("XYFZ"));
  std::mt19937 rng(13);
  const std::vector<Eigen::Vector3d> points = randomPoints(rng, 7, 400);
  std::vector<PointError> out(3);
  Workspace ws, single;
  evaluateBatch(model, ws, points, out);
  for (std::size_t i = 0; i < out.size(); ++i) {
    expectSame(out[i].errorMm, evaluate(model, single, points[i]).errorMm, "errorMm");
  }
  std::vector<OffsetSolution> offsets(2);
  solveOffsetBatch(model, ws, points, offsets);
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    expectSame(offsets[i].offsetMm, solveOffset(model, single, points[i]).offsetMm, "offsetMm");
  }
}

// The baseline (SSE2) build of the batch against the dispatched one, as kernels_test does for
// the single-point functions.
TEST(Batch, BaselineBuildAgrees) {
  std::mt19937 rng(17);
  const detail::Kernels& generic = detail::genericKernels();
  for (const char* topology : {"XYFZ", "FXYZ", "YXZF"}) {
    const MachineModel model(testing::fullModel(topology, 101, 1e-3));
    const std::vector<Eigen::Vector3d> points = randomPoints(rng, 23, 500);
    std::vector<PointError> out(points.size()), outGeneric(points.size());
    Workspace ws;
    for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
      evaluateBatch(model, ws, points, out, mode);
      generic.many(model, ws, points.data(), nullptr, 0, outGeneric.data(), points.size(), mode);
      for (std::size_t i = 0; i < points.size(); ++i) {
        expectSame(out[i].errorMm, outGeneric[i].errorMm, "errorMm");
        expectSame(out[i].angularErrorRad, outGeneric[i].angularErrorRad, "angularErrorRad");
        EXPECT_EQ(out[i].clampedAxes, outGeneric[i].clampedAxes);
      }
    }
    std::vector<OffsetSolution> offsets(points.size()), offsetsGeneric(points.size());
    solveOffsetBatch(model, ws, points, offsets);
    generic.solveMany(model, ws, points.data(), nullptr, 0, offsetsGeneric.data(), points.size(),
                      OffsetOptions{});
    for (std::size_t i = 0; i < points.size(); ++i) {
      expectSame(offsets[i].offsetMm, offsetsGeneric[i].offsetMm, "offsetMm");
      EXPECT_EQ(offsets[i].converged, offsetsGeneric[i].converged);
    }
  }
}

}  // namespace
}  // namespace volcomp::model
