#include "volcomp/model/machine_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "model_builders.hpp"
#include "volcomp/model/composition.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::model {
namespace {

constexpr double kUrad = 1e-6;
const Eigen::Vector3d kQ(200, 50, -30);

// A worked example's result from the fast path (held to 1e-15 mm of the closed forms) and from the
// reference composition (1e-13 mm: it forms p - p0 from points of a few 100 mm).
struct PathResult {
  const char* path;
  PointError error;
  double toleranceMm;
};

std::array<PathResult, 2> bothPaths(const MachineModel& model, const Eigen::Vector3d& q) {
  Workspace ws;
  return {{{"evaluate", evaluate(model, ws, q), 1e-15},
           {"evaluateReference", evaluateReference(model, q), 1e-13}}};
}

MachineModelSpec specWith(const std::string& topology, Eigen::Vector3d tool = {0, 0, 100}) {
  MachineModelSpec spec;
  spec.topology = topology;
  spec.toolMm = tool;
  return spec;
}

// Spec section 4, example 1. FXYZ: H_FT = C_X C_Y C_Z Trans(t); only X pitches, so the point
// (0, y, z + 100) = (0, 50, 70) is rotated by Ry(b), b = 100 urad:
// E = (70 sin b, 0, 70 (cos b - 1)) = (0.00699999998833, 0, -3.49999999708e-7) ~ (+0.007, 0,
// -3.5e-7).
TEST(WorkedExamples, FXYZPitchOfXIsAbbe) {
  MachineModelSpec spec = specWith("FXYZ");
  spec.motion[motionIndex(Axis::X, MotionKind::EB)] = 100 * kUrad;
  const MachineModel model(spec);
  for (const auto& [path, e, tolerance] : bothPaths(model, kQ)) {
    SCOPED_TRACE(path);
    EXPECT_NEAR(e.errorMm.x(), 0.007, 5e-10);  // digits given
    EXPECT_NEAR(e.errorMm.y(), 0.0, tolerance);
    EXPECT_NEAR(e.errorMm.z(), -3.5e-7, 5e-14);
    EXPECT_NEAR(e.errorMm.x(), 0.00699999998833333334, tolerance);
    EXPECT_NEAR(e.errorMm.z(), -3.49999999708333333e-7, tolerance);
    EXPECT_NEAR(e.angularErrorRad.y(), 100 * kUrad, 1e-18);
    EXPECT_EQ(e.clampedAxes, 0);
  }
}

// Example 2. XYFZ: p = C_X^-1 C_Y^-1 (C_Z t) = Ry(-b) ((0, 0, 70) + (0, 50, 0) + (200, 0, 0)):
// E = (200 cos b - 70 sin b - 200, 0, 200 sin b + 70 cos b - 70)
//   = (-0.0070009999988325, 0, 0.019999649966667) ~ (-0.007001, 0, +0.019999650).
TEST(WorkedExamples, XYFZPitchOfXTiltsTheTable) {
  MachineModelSpec spec = specWith("XYFZ");
  spec.motion[motionIndex(Axis::X, MotionKind::EB)] = 100 * kUrad;
  const MachineModel model(spec);
  for (const auto& [path, e, tolerance] : bothPaths(model, kQ)) {
    SCOPED_TRACE(path);
    EXPECT_NEAR(e.errorMm.x(), -0.007001, 5e-10);
    EXPECT_NEAR(e.errorMm.y(), 0.0, tolerance);
    EXPECT_NEAR(e.errorMm.z(), 0.019999650, 5e-10);
    EXPECT_NEAR(e.errorMm.x(), -0.00700099998833250001, tolerance);
    EXPECT_NEAR(e.errorMm.z(), 0.01999964996666695835, tolerance);
    EXPECT_NEAR(e.angularErrorRad.y(), -100 * kUrad, 1e-18);
  }
}

// Example 3. FXYZ, no tool, EC0Y = 100 urad so d_Y = (-sin c, cos c, 0); EXX(250) = 15 um.
// E = (0.015 - 100 sin c, 100 (cos c - 1), 0) = (0.0050000000166667, -4.99999999583e-7, 0).
// Offset: E_y(q + o) + o_y = (100 + o_y)(cos c - 1) + o_y = 0 -> o_y = 100 (1 - cos c) / cos c
// = 5.00000002083e-7; E_x(q + o) + o_x = 0.015 + 1e-4 o_x - (100 + o_y) sin c + o_x = 0 (the
// table's slope is 10 um / 100 mm) -> o_x = (-0.015 + (100 + o_y) sin c) / 1.0001
// = -0.004999500016665 ~ -0.0049995.
TEST(WorkedExamples, FXYZSquarenessAndLinearTableWithOffset) {
  MachineModelSpec spec = specWith("FXYZ", Eigen::Vector3d::Zero());
  spec.locationRad[locationIndex(Axis::Y, 2)] = 100 * kUrad;
  TableSpec exx;
  exx.positionsMm = {0, 100, 200, 300};
  exx.values = {0, 5e-3, 10e-3, 20e-3};
  spec.motion[motionIndex(Axis::X, MotionKind::EX)] = exx;
  const MachineModel model(spec);
  const Eigen::Vector3d q(250, 100, 0);
  for (const auto& [path, e, tolerance] : bothPaths(model, q)) {
    SCOPED_TRACE(path);
    EXPECT_NEAR(e.errorMm.x(), 0.005, 5e-10);
    EXPECT_NEAR(e.errorMm.y(), -5.0e-7, 5e-14);
    EXPECT_NEAR(e.errorMm.z(), 0.0, tolerance);
    EXPECT_NEAR(e.errorMm.x(), 0.00500000001666666666, tolerance);
    EXPECT_NEAR(e.errorMm.y(), -4.99999999583333333e-7, tolerance / 100);
  }

  Workspace ws;
  std::array<OffsetSolution, 1> batch;
  solveOffsetBatch(model, ws, std::span(&q, 1), batch);
  for (const OffsetSolution& o : {solveOffset(model, ws, q), batch[0]}) {
    EXPECT_TRUE(o.converged);
    EXPECT_LT(o.residualMm, 1e-9);
    EXPECT_NEAR(o.offsetMm.x(), -0.0049995, 5e-11);
    EXPECT_NEAR(o.offsetMm.y(), 5.0e-7, 5e-14);
    EXPECT_NEAR(o.offsetMm.z(), 0.0, 1e-15);
    // The solve stops once |p(q + o) - p0(q)| < 1e-9 mm, so o is that close to the root.
    EXPECT_NEAR(o.offsetMm.x(), -0.00499950001666500003, 1e-9);
    EXPECT_NEAR(o.offsetMm.y(), 5.00000002083333334e-7, 1e-9);
  }
}

TEST(MachineModel, ZeroModelIsZeroInAllTopologies) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-800, 800);
  for (const std::string& topology : allTopologies()) {
    MachineModelSpec spec = specWith(topology, Eigen::Vector3d(12, -7, 150));
    spec.workpieceMm = Eigen::Vector3d(100, 40, 25);
    const MachineModel model(spec);
    Workspace ws;
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d q(u(rng), u(rng), u(rng));
      for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
        const PointError e = evaluate(model, ws, q, {}, mode);
        // p - p0 of about 1e3 mm numbers: a few ulps of 1e3.
        EXPECT_LT(e.errorMm.norm(), 1e-12) << topology;
        EXPECT_EQ(e.angularErrorRad.norm(), 0.0) << topology;
      }
      const OffsetSolution o = solveOffset(model, ws, q);
      EXPECT_TRUE(o.converged) << topology;
      EXPECT_LT(o.offsetMm.norm(), 1e-12) << topology;
    }
  }
}

TEST(MachineModel, AxisDirections) {
  // d_Y = Rz(c) e_Y = (-sin c, cos c, 0) for EC0Y = c; d_Z = Ry(b) Rx(a) e_Z for EA0Z, EB0Z.
  MachineModelSpec spec;
  spec.locationRad[locationIndex(Axis::Y, 2)] = 1e-3;
  spec.locationRad[locationIndex(Axis::Z, 0)] = 2e-3;
  spec.locationRad[locationIndex(Axis::Z, 1)] = -3e-3;
  const MachineModel model(spec);
  EXPECT_LT((model.axisDirection(Axis::X) - Eigen::Vector3d::UnitX()).norm(), 1e-18);
  EXPECT_LT(
      (model.axisDirection(Axis::Y) - Eigen::Vector3d(-std::sin(1e-3), std::cos(1e-3), 0)).norm(),
      1e-16);
  const Eigen::Vector3d dz(std::sin(-3e-3) * std::cos(2e-3), -std::sin(2e-3),
                           std::cos(-3e-3) * std::cos(2e-3));
  EXPECT_LT((model.axisDirection(Axis::Z) - dz).norm(), 1e-16);
}

TEST(MachineModel, TravelClampsErrorFunctionsNotTheMotion) {
  // X travel [0, 300]; EXX linear 0 -> 30 um over [0, 300]; EBX the polynomial 1e-7 x (rad),
  // which would keep growing. At x = 400 both are evaluated at 300: EXX = 0.03 mm, EBX = 3e-5 rad,
  // while the nominal motion still goes to 400 (E is relative to p0 at 400). FXYZ, tool
  // (0, 0, 100), q = (400, 0, 0): the X carriage pitches the arm (0, 0, 100), so
  // E = (0.03 + 100 sin(3e-5), 0, 100 (cos(3e-5) - 1)), with cos - 1 = -2 sin^2(1.5e-5).
  MachineModelSpec spec = specWith("FXYZ");
  spec.travelMm[0] = std::array<double, 2>{0, 300};
  TableSpec exx;
  exx.positionsMm = {0, 300};
  exx.values = {0, 0.03};
  spec.motion[motionIndex(Axis::X, MotionKind::EX)] = exx;
  spec.motion[motionIndex(Axis::X, MotionKind::EB)] = PolynomialSpec{{0, 1e-7}};
  const MachineModel model(spec);
  Workspace ws;
  const PointError e = evaluate(model, ws, Eigen::Vector3d(400, 0, 0));
  EXPECT_EQ(e.clampedAxes, 0b001);
  EXPECT_NEAR(e.errorMm.x(), 0.03 + 100 * std::sin(3e-5), 1e-15);
  EXPECT_NEAR(e.errorMm.z(), -200 * std::sin(1.5e-5) * std::sin(1.5e-5), 1e-20);
  // Inside the travel nothing is flagged; below it the start values (0) are used.
  EXPECT_EQ(evaluate(model, ws, Eigen::Vector3d(150, 0, 0)).clampedAxes, 0);
  const PointError below = evaluate(model, ws, Eigen::Vector3d(-20, 1e4, 0));
  EXPECT_EQ(below.clampedAxes, 0b001);  // Y and Z have no travel: never clamped
  EXPECT_LT(below.errorMm.norm(), 1e-11);
  // The offset solve reports the clamping too.
  EXPECT_EQ(solveOffset(model, ws, Eigen::Vector3d(400, 0, 0)).clampedAxes, 0b001);
}

TEST(MachineModel, ClampFlagsPerAxis) {
  MachineModelSpec spec = specWith("XYFZ");
  spec.travelMm = {std::array<double, 2>{0, 10}, std::array<double, 2>{0, 10},
                   std::array<double, 2>{-10, 0}};
  const MachineModel model(spec);
  Workspace ws;
  EXPECT_EQ(evaluate(model, ws, Eigen::Vector3d(5, 11, 1)).clampedAxes, 0b110);
  EXPECT_EQ(evaluate(model, ws, Eigen::Vector3d(-1, 5, -5)).clampedAxes, 0b001);
  EXPECT_EQ(evaluate(model, ws, Eigen::Vector3d(10, 0, -10)).clampedAxes, 0);
}

TEST(MachineModel, DirectionSelectsCurve) {
  // EXX bidirectional: positive 0 -> 10 um, negative 4 -> 6 um over [0, 100]; at x = 50:
  // positive 5 um, negative 5 um, mean 5 um; at x = 75: 7.5, 5.5, mean 6.5 um. FXYZ: E_x = EXX.
  MachineModelSpec spec = specWith("FXYZ");
  TableSpec exx;
  exx.positionsMm = {0, 100};
  exx.values = {0, 0.010};
  exx.valuesNegative = {0.004, 0.006};
  spec.motion[0] = exx;
  const MachineModel model(spec);
  Workspace ws;
  const Eigen::Vector3d q(75, 0, 0);
  using D = Direction;
  EXPECT_NEAR(evaluate(model, ws, q, {D::Positive, D::Negative, D::Negative}).errorMm.x(), 0.0075,
              1e-15);
  EXPECT_NEAR(evaluate(model, ws, q, {D::Negative, D::Positive, D::Positive}).errorMm.x(), 0.0055,
              1e-15);
  EXPECT_NEAR(evaluate(model, ws, q).errorMm.x(), 0.0065, 1e-15);
}

TEST(MachineModel, GridTermAddedToPosition) {
  // XYFZ with a Z grid over (X, Y) = 2 um at every node: E = (0, 0, 0.002) exactly; with the
  // tool offset override the grid is unchanged.
  MachineModelSpec spec = specWith("XYFZ");
  GridSpec grid;
  grid.component = 2;
  grid.over = {Axis::X, Axis::Y};
  grid.axesMm = {{0, 500}, {0, 500}};
  grid.valuesMm = {0.002, 0.002, 0.002, 0.002};
  spec.grids = {grid};
  const MachineModel model(spec);
  Workspace ws;
  const PointError e = evaluate(model, ws, Eigen::Vector3d(100, 200, -50));
  EXPECT_LT((e.errorMm - Eigen::Vector3d(0, 0, 0.002)).norm(), 1e-13);
  const PointError t =
      evaluate(model, ws, Eigen::Vector3d(100, 200, -50), Eigen::Vector3d(5, 5, 300));
  EXPECT_LT((t.errorMm - Eigen::Vector3d(0, 0, 0.002)).norm(), 1e-13);
  const OffsetSolution o = solveOffset(model, ws, Eigen::Vector3d(100, 200, -50));
  EXPECT_LT((o.offsetMm - Eigen::Vector3d(0, 0, -0.002)).norm(), 1e-12);
}

TEST(MachineModel, ExactAngularErrorIsLogOfComposedRotation) {
  // FXYZ with ECX = 1e-4 and EAY = 2e-4: rot(H_WT) = R_X R_Y = Rz(1e-4) Rx(2e-4); workpiece-side
  // XYZF: rot(H_WT) = R_X^T R_Y^T R_Z^T = (Rz(1e-4))^T (Rx(2e-4))^T.
  MachineModelSpec spec = specWith("FXYZ");
  spec.motion[motionIndex(Axis::X, MotionKind::EC)] = 1e-4;
  spec.motion[motionIndex(Axis::Y, MotionKind::EA)] = 2e-4;
  Workspace ws;
  const Eigen::Vector3d w = evaluate(MachineModel(spec), ws, kQ).angularErrorRad;
  EXPECT_LT((w - rotationVector(rotationZYX(0, 0, 1e-4) * rotationZYX(2e-4, 0, 0))).norm(), 1e-18);
  spec.topology = "XYZF";
  const Eigen::Vector3d v = evaluate(MachineModel(spec), ws, kQ).angularErrorRad;
  EXPECT_LT((v - rotationVector(rotationZYX(0, 0, 1e-4).transpose() *
                                rotationZYX(2e-4, 0, 0).transpose()))
                .norm(),
            1e-18);
  // First order: the angles add with the side's sign.
  EXPECT_LT((v + Eigen::Vector3d(2e-4, 0, 1e-4)).norm(), 1e-7);
}

TEST(MachineModel, ComposeErrorUsesSuppliedValues) {
  // Calibration supplies its own component values: EBX = 1e-4 in FXYZ gives example 1.
  const MachineModel model(specWith("FXYZ"));
  Workspace ws;
  MotionValues values{};
  values[motionIndex(Axis::X, MotionKind::EB)] = 1e-4;
  const PointError e = composeError(model, ws, kQ, values, Eigen::Vector3d(0, 0, 100));
  EXPECT_NEAR(e.errorMm.x(), 0.00699999998833333334, 1e-15);
  MotionValues out{};
  EXPECT_EQ(evaluateMotion(model, kQ, {}, out), 0);
  EXPECT_EQ(out, MotionValues{});
}

TEST(MachineModel, CopiesEvaluateTheSame) {
  std::mt19937 rng(3);
  const MachineModel original(testing::randomModel(rng, 1e-3, 500, 200));
  const MachineModel copy = original;
  Workspace ws;
  const Eigen::Vector3d q(120, -230, 45);
  EXPECT_EQ(evaluate(original, ws, q).errorMm, evaluate(copy, ws, q).errorMm);
}

TEST(MachineModel, NonConvergenceIsReported) {
  // EXX with slope 0.5 mm/mm (0 -> 50 mm over [0, 100]), FXYZ, q_x = 50: E_x(q + o) = 25 + 0.5 o,
  // so the step o <- o - (E(q + o) + o) = -25 - 0.5 o contracts by only 1/2: from o = -25 the
  // distance to o* = -25 / 1.5 is 8.3 mm, and 3 iterations leave a residual of about 1 mm.
  MachineModelSpec spec = specWith("FXYZ");
  TableSpec exx;
  exx.positionsMm = {0, 100};
  exx.values = {0, 50};
  spec.motion[0] = exx;
  const MachineModel model(spec);
  Workspace ws;
  OffsetOptions options;
  options.maxIterations = 3;
  const OffsetSolution o = solveOffset(model, ws, Eigen::Vector3d(50, 0, 0), {}, options);
  EXPECT_FALSE(o.converged);
  EXPECT_EQ(o.iterations, 3);
  EXPECT_GT(o.residualMm, 1e-9);
  // With enough iterations it gets there: o = -E / (1 + 0.5) = -25 / 1.5.
  options.maxIterations = 100;
  const OffsetSolution full = solveOffset(model, ws, Eigen::Vector3d(50, 0, 0), {}, options);
  EXPECT_TRUE(full.converged);
  EXPECT_NEAR(full.offsetMm.x(), -25.0 / 1.5, 1e-8);
}

TEST(MachineModel, RejectsBadData) {
  auto bad = [](MachineModelSpec spec, const char* needle) {
    try {
      MachineModel model(std::move(spec));
      ADD_FAILURE() << "no ModelError for " << needle;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  MachineModelSpec spec;
  spec.topology = "FXYY";
  bad(spec, "topology");
  spec = MachineModelSpec{};
  spec.topology = "xyfz";
  bad(spec, "topology");
  spec = MachineModelSpec{};
  TableSpec even;
  even.positionsMm = {0, 1, 2, 3};
  even.values = {0, 0, 0, 0};
  even.interpolation = Interpolation::Quadratic;
  spec.motion[motionIndex(Axis::Y, MotionKind::EB)] = even;
  bad(spec, "EBY");
  spec = MachineModelSpec{};
  TableSpec decreasing;
  decreasing.positionsMm = {0, 2, 1};
  decreasing.values = {0, 0, 0};
  spec.motion[motionIndex(Axis::Z, MotionKind::EX)] = decreasing;
  bad(spec, "EXZ");
  spec = MachineModelSpec{};
  spec.locationRad[5] = std::numeric_limits<double>::infinity();
  bad(spec, "EC0Y");
  spec = MachineModelSpec{};
  spec.travelMm[1] = std::array<double, 2>{10, 0};
  bad(spec, "travel");
  spec = MachineModelSpec{};
  spec.toolMm.x() = std::numeric_limits<double>::quiet_NaN();
  bad(spec, "tool");
  spec = MachineModelSpec{};
  GridSpec grid;
  grid.over = {Axis::X, Axis::Y};
  grid.axesMm = {{0, 1}, {0, 1}};
  grid.valuesMm = {0, 0, 0};
  spec.grids = {grid};
  bad(spec, "grids[0]");
}

}  // namespace
}  // namespace volcomp::model

namespace volcomp::model {
namespace {

TEST(MachineModel, EvaluateMotionMatchesErrorFunctions) {
  // evaluateMotion groups tables and has a fast path for six uniform tables on one axis; it must
  // give what each ErrorFunction gives on its own, at the travel-clamped position, for every
  // direction. X: six uniform bidirectional tables (fast path); Y: mixed kinds incl. a
  // polynomial and a non-uniform table; Z: constants and one quadratic table.
  MachineModelSpec spec;
  spec.topology = "XYFZ";
  spec.travelMm = {std::array<double, 2>{0, 800}, std::array<double, 2>{-50, 450}, std::nullopt};
  for (int kind = 0; kind < 6; ++kind) {
    TableSpec t = testing::smoothTable(0, 800, 41, 0.01, kind, Interpolation::Cubic);
    t.interpolation = kind % 2 ? Interpolation::Linear : Interpolation::Cubic;
    t.valuesNegative = t.values;
    for (double& value : t.valuesNegative) value = -0.5 * value + 0.001;
    spec.motion[motionIndex(Axis::X, static_cast<MotionKind>(kind))] = t;
  }
  spec.motion[motionIndex(Axis::Y, MotionKind::EX)] =
      testing::smoothTable(0, 400, 21, 0.01, 0.5, Interpolation::Linear);
  spec.motion[motionIndex(Axis::Y, MotionKind::EY)] =
      testing::smoothTable(0, 400, 21, 0.01, 1.5, Interpolation::Quadratic);
  spec.motion[motionIndex(Axis::Y, MotionKind::EZ)] = PolynomialSpec{{1e-3, 2e-6, -1e-9}};
  TableSpec uneven;
  uneven.positionsMm = {-50, 0, 10, 200, 450};
  uneven.values = {1e-4, -2e-4, 0, 3e-4, 1e-4};
  uneven.interpolation = Interpolation::Cubic;
  spec.motion[motionIndex(Axis::Y, MotionKind::EC)] = uneven;
  spec.motion[motionIndex(Axis::Z, MotionKind::EA)] = 2e-5;
  spec.motion[motionIndex(Axis::Z, MotionKind::EZ)] =
      testing::smoothTable(-300, 0, 7, 0.005, 0.2, Interpolation::Quadratic);
  const MachineModel model(spec);
  for (const Direction d : {Direction::Positive, Direction::Negative, Direction::Unknown}) {
    const Directions directions = {d, d, d};
    for (double s = -0.1; s <= 1.1; s += 0.0037) {
      const Eigen::Vector3d q(800 * s, 500 * s - 50, -300 * s);
      MotionValues values{};
      const std::uint8_t clamped = evaluateMotion(model, q, directions, values);
      const std::uint8_t expectedClamped = static_cast<std::uint8_t>((s < 0 || s > 1) ? 0b011 : 0);
      EXPECT_EQ(clamped, expectedClamped) << s;
      const Eigen::Vector3d held(std::clamp(q.x(), 0.0, 800.0), std::clamp(q.y(), -50.0, 450.0),
                                 q.z());
      for (int i = 0; i < 18; ++i) {
        EXPECT_NEAR(values[i], model.motion(i).value(held[i / 6], d), 1e-15)
            << motionName(i) << " at s = " << s;
      }
    }
  }
}

}  // namespace
}  // namespace volcomp::model

namespace volcomp::model {
namespace {

TEST(MachineModel, NonFinitePositionsStayInsideTheTables) {
  // A NaN or infinite position (a broken reading) must not index outside any table: NaN gives a
  // NaN error (not a crash), infinities are held at the table ends.
  std::mt19937 rng(11);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const MachineModelSpec& spec :
       {testing::fullModel("XYFZ"), testing::randomModel(rng, 1e-3, 500, 100)}) {
    MachineModelSpec unbounded = spec;
    unbounded.travelMm = {};
    for (const MachineModel& model : {MachineModel(spec), MachineModel(unbounded)}) {
      Workspace ws;
      EXPECT_TRUE(evaluate(model, ws, Eigen::Vector3d(nan, 10, -10)).errorMm.hasNaN());
      EXPECT_FALSE(solveOffset(model, ws, Eigen::Vector3d(10, nan, -10)).converged);
      MotionValues values{};
      evaluateMotion(model, Eigen::Vector3d(inf, -inf, inf), {}, values);
      for (int i = 0; i < 18; ++i) {
        if (std::holds_alternative<TableSpec>(model.spec().motion[i])) {
          EXPECT_TRUE(std::isfinite(values[i])) << motionName(i);
        }
      }
    }
  }
}

TEST(MachineModel, OutOfRangeDirectionCountsAsUnknown) {
  MachineModelSpec spec;
  TableSpec exx;
  exx.positionsMm = {0, 100};
  exx.values = {0, 0.010};
  exx.valuesNegative = {0.004, 0.006};
  spec.motion[0] = exx;
  const MachineModel model(spec);
  Workspace ws;
  const Direction odd = static_cast<Direction>(5);
  EXPECT_EQ(evaluate(model, ws, Eigen::Vector3d(75, 0, 0), {odd, odd, odd}).errorMm.x(),
            evaluate(model, ws, Eigen::Vector3d(75, 0, 0)).errorMm.x());
}

}  // namespace
}  // namespace volcomp::model
