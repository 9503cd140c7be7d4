// One test per error component (18 motion errors, 9 location errors), each in the tool-side
// topology FXYZ and the workpiece-side topology XYZF, with the expected value derived by hand.
//
// Common set-up: q = (x, y, z) = (200, 50, -30) mm, tool t = (10, 20, 100) mm, workpiece w = 0,
// one component non-zero: translations 0.005 mm, angles theta = 1e-4 rad.
//
// FXYZ: p = C_X C_Y C_Z t with C_K = Trans(q_K d_K + e_K) R_K. A rotation R_K of carriage K turns
// everything it carries, i.e. the arm from its origin to the tool point:
//   arm_X = (0, y, z) + t = (10, 70, 70), arm_Y = (0, 0, z) + t = (10, 20, 70), arm_Z = t.
// E = (R_K - I) arm_K ~ theta (axis x arm_K), second order theta^2/2 |arm| < 6e-7 mm.
// Angular error: exactly +theta about the axis of the rotation.
//
// XYZF: H_FW = C_Z C_Y C_X, H_FT = Trans(t), p = C_X^-1 C_Y^-1 C_Z^-1 t with
// C_K^-1 v = R_K^T (v + q_K d_K - e_K). A rotation R_K^T of carriage K turns the vector
//   a_Z = t + (0, 0, z) = (10, 20, 70), a_Y = a_Z + (0, y, 0) = (10, 70, 70),
//   a_X = a_Y + (x, 0, 0) = (210, 70, 70),
// E = (R_K^T - I) a_K ~ -theta (axis x a_K), second order theta^2/2 |a| < 1.2e-6 mm.
// Angular error: exactly -theta about the axis.
//
// Cross products used: e_x x (a, b, c) = (0, -c, b), e_y x (a, b, c) = (c, 0, -a),
// e_z x (a, b, c) = (-b, a, 0).
//
// Translations: FXYZ adds e_K (no rotation anywhere), E = +e exactly; XYZF subtracts it,
// E = -e exactly.
//
// Location errors: d_K = Rz(c) Ry(b) Rx(a) e_K only changes the direction of the commanded
// motion q_K d_K, on either side (C_K^-1 adds +q_K d_K on the workpiece side, C_K adds it on the
// tool side), so in both topologies E = q_K (d_K - e_K) exactly, with
//   Ry(b) e_x = (cos b, 0, -sin b), Rz(c) e_x = (cos c, sin c, 0), Rx(a) e_y = (0, cos a, sin a),
//   Rz(c) e_y = (-sin c, cos c, 0), Rx(a) e_z = (0, -sin a, cos a), Ry(b) e_z = (sin b, 0, cos b),
// and a rotation about the axis' own direction (EA0X, EB0Y, EC0Z) changes nothing.
// With theta = 1e-4: cos - 1 = -4.99999999583e-9, sin = 9.99999999833e-5.

#include <string>

#include <gtest/gtest.h>

#include "volcomp/model/composition.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {
namespace {

struct ComponentCase {
  const char* name;  // test name: component and topology
  const char* topology;
  bool location;  // location error (index into locationRad) or motion error (motionIndex)
  int index;
  double value;
  Eigen::Vector3d error;
  Eigen::Vector3d angular;
  double tolerance;
};

constexpr double kTheta = 1e-4;
constexpr double kFirst = 1.5e-6;  // covers the neglected second-order terms
constexpr double kExact = 1e-15;

int m(Axis axis, MotionKind kind) {
  return motionIndex(axis, kind);
}

const ComponentCase kCases[] = {
    // --- Motion translations: FXYZ E = +0.005 along the component, XYZF E = -0.005.
    {"EXX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EX),
     0.005,
     {0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EY),
     0.005,
     {0, 0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EZ),
     0.005,
     {0, 0, 0.005},
     {0, 0, 0},
     kExact},
    {"EXY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EX),
     0.005,
     {0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EY),
     0.005,
     {0, 0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EZ),
     0.005,
     {0, 0, 0.005},
     {0, 0, 0},
     kExact},
    {"EXZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EX),
     0.005,
     {0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EY),
     0.005,
     {0, 0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EZ),
     0.005,
     {0, 0, 0.005},
     {0, 0, 0},
     kExact},
    {"EXX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EX),
     0.005,
     {-0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EY),
     0.005,
     {0, -0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EZ),
     0.005,
     {0, 0, -0.005},
     {0, 0, 0},
     kExact},
    {"EXY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EX),
     0.005,
     {-0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EY),
     0.005,
     {0, -0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EZ),
     0.005,
     {0, 0, -0.005},
     {0, 0, 0},
     kExact},
    {"EXZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EX),
     0.005,
     {-0.005, 0, 0},
     {0, 0, 0},
     kExact},
    {"EYZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EY),
     0.005,
     {0, -0.005, 0},
     {0, 0, 0},
     kExact},
    {"EZZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EZ),
     0.005,
     {0, 0, -0.005},
     {0, 0, 0},
     kExact},

    // --- Motion rotations, FXYZ: E ~ theta (axis x arm_K).
    // EAX: e_x x (10, 70, 70) = (0, -70, 70) -> (0, -0.007, 0.007)
    {"EAX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EA),
     kTheta,
     {0, -0.007, 0.007},
     {kTheta, 0, 0},
     kFirst},
    // EBX: e_y x (10, 70, 70) = (70, 0, -10) -> (0.007, 0, -0.001)
    {"EBX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EB),
     kTheta,
     {0.007, 0, -0.001},
     {0, kTheta, 0},
     kFirst},
    // ECX: e_z x (10, 70, 70) = (-70, 10, 0) -> (-0.007, 0.001, 0)
    {"ECX_FXYZ",
     "FXYZ",
     false,
     m(Axis::X, MotionKind::EC),
     kTheta,
     {-0.007, 0.001, 0},
     {0, 0, kTheta},
     kFirst},
    // EAY: e_x x (10, 20, 70) = (0, -70, 20) -> (0, -0.007, 0.002)
    {"EAY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EA),
     kTheta,
     {0, -0.007, 0.002},
     {kTheta, 0, 0},
     kFirst},
    // EBY: e_y x (10, 20, 70) = (70, 0, -10) -> (0.007, 0, -0.001)
    {"EBY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EB),
     kTheta,
     {0.007, 0, -0.001},
     {0, kTheta, 0},
     kFirst},
    // ECY: e_z x (10, 20, 70) = (-20, 10, 0) -> (-0.002, 0.001, 0)
    {"ECY_FXYZ",
     "FXYZ",
     false,
     m(Axis::Y, MotionKind::EC),
     kTheta,
     {-0.002, 0.001, 0},
     {0, 0, kTheta},
     kFirst},
    // EAZ: e_x x (10, 20, 100) = (0, -100, 20) -> (0, -0.01, 0.002)
    {"EAZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EA),
     kTheta,
     {0, -0.01, 0.002},
     {kTheta, 0, 0},
     kFirst},
    // EBZ: e_y x (10, 20, 100) = (100, 0, -10) -> (0.01, 0, -0.001)
    {"EBZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EB),
     kTheta,
     {0.01, 0, -0.001},
     {0, kTheta, 0},
     kFirst},
    // ECZ: e_z x (10, 20, 100) = (-20, 10, 0) -> (-0.002, 0.001, 0)
    {"ECZ_FXYZ",
     "FXYZ",
     false,
     m(Axis::Z, MotionKind::EC),
     kTheta,
     {-0.002, 0.001, 0},
     {0, 0, kTheta},
     kFirst},

    // --- Motion rotations, XYZF: E ~ -theta (axis x a_K).
    // EAX: -e_x x (210, 70, 70) = (0, 70, -70) -> (0, 0.007, -0.007)
    {"EAX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EA),
     kTheta,
     {0, 0.007, -0.007},
     {-kTheta, 0, 0},
     kFirst},
    // EBX: -e_y x (210, 70, 70) = (-70, 0, 210) -> (-0.007, 0, 0.021)
    {"EBX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EB),
     kTheta,
     {-0.007, 0, 0.021},
     {0, -kTheta, 0},
     kFirst},
    // ECX: -e_z x (210, 70, 70) = (70, -210, 0) -> (0.007, -0.021, 0)
    {"ECX_XYZF",
     "XYZF",
     false,
     m(Axis::X, MotionKind::EC),
     kTheta,
     {0.007, -0.021, 0},
     {0, 0, -kTheta},
     kFirst},
    // EAY: -e_x x (10, 70, 70) = (0, 70, -70) -> (0, 0.007, -0.007)
    {"EAY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EA),
     kTheta,
     {0, 0.007, -0.007},
     {-kTheta, 0, 0},
     kFirst},
    // EBY: -e_y x (10, 70, 70) = (-70, 0, 10) -> (-0.007, 0, 0.001)
    {"EBY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EB),
     kTheta,
     {-0.007, 0, 0.001},
     {0, -kTheta, 0},
     kFirst},
    // ECY: -e_z x (10, 70, 70) = (70, -10, 0) -> (0.007, -0.001, 0)
    {"ECY_XYZF",
     "XYZF",
     false,
     m(Axis::Y, MotionKind::EC),
     kTheta,
     {0.007, -0.001, 0},
     {0, 0, -kTheta},
     kFirst},
    // EAZ: -e_x x (10, 20, 70) = (0, 70, -20) -> (0, 0.007, -0.002)
    {"EAZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EA),
     kTheta,
     {0, 0.007, -0.002},
     {-kTheta, 0, 0},
     kFirst},
    // EBZ: -e_y x (10, 20, 70) = (-70, 0, 10) -> (-0.007, 0, 0.001)
    {"EBZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EB),
     kTheta,
     {-0.007, 0, 0.001},
     {0, -kTheta, 0},
     kFirst},
    // ECZ: -e_z x (10, 20, 70) = (20, -10, 0) -> (0.002, -0.001, 0)
    {"ECZ_XYZF",
     "XYZF",
     false,
     m(Axis::Z, MotionKind::EC),
     kTheta,
     {0.002, -0.001, 0},
     {0, 0, -kTheta},
     kFirst},

    // --- Location errors, the same in both topologies: E = q_K (d_K - e_K).
    // EA0X: Rx(a) e_x = e_x -> 0
    {"EA0X_FXYZ", "FXYZ", true, 0, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
    {"EA0X_XYZF", "XYZF", true, 0, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
    // EB0X: 200 (cos b - 1, 0, -sin b)
    {"EB0X_FXYZ",
     "FXYZ",
     true,
     1,
     kTheta,
     {-9.9999999916667941e-7, 0, -0.019999999966666667},
     {0, 0, 0},
     kExact},
    {"EB0X_XYZF",
     "XYZF",
     true,
     1,
     kTheta,
     {-9.9999999916667941e-7, 0, -0.019999999966666667},
     {0, 0, 0},
     kExact},
    // EC0X: 200 (cos c - 1, sin c, 0)
    {"EC0X_FXYZ",
     "FXYZ",
     true,
     2,
     kTheta,
     {-9.9999999916667941e-7, 0.019999999966666667, 0},
     {0, 0, 0},
     kExact},
    {"EC0X_XYZF",
     "XYZF",
     true,
     2,
     kTheta,
     {-9.9999999916667941e-7, 0.019999999966666667, 0},
     {0, 0, 0},
     kExact},
    // EA0Y: 50 (0, cos a - 1, sin a)
    {"EA0Y_FXYZ",
     "FXYZ",
     true,
     3,
     kTheta,
     {0, -2.4999999979166985e-7, 0.0049999999916666667},
     {0, 0, 0},
     kExact},
    {"EA0Y_XYZF",
     "XYZF",
     true,
     3,
     kTheta,
     {0, -2.4999999979166985e-7, 0.0049999999916666667},
     {0, 0, 0},
     kExact},
    // EB0Y: Ry(b) e_y = e_y -> 0
    {"EB0Y_FXYZ", "FXYZ", true, 4, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
    {"EB0Y_XYZF", "XYZF", true, 4, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
    // EC0Y: 50 (-sin c, cos c - 1, 0)
    {"EC0Y_FXYZ",
     "FXYZ",
     true,
     5,
     kTheta,
     {-0.0049999999916666667, -2.4999999979166985e-7, 0},
     {0, 0, 0},
     kExact},
    {"EC0Y_XYZF",
     "XYZF",
     true,
     5,
     kTheta,
     {-0.0049999999916666667, -2.4999999979166985e-7, 0},
     {0, 0, 0},
     kExact},
    // EA0Z: -30 (0, -sin a, cos a - 1)
    {"EA0Z_FXYZ",
     "FXYZ",
     true,
     6,
     kTheta,
     {0, 0.0029999999950000000, 1.4999999987500191e-7},
     {0, 0, 0},
     kExact},
    {"EA0Z_XYZF",
     "XYZF",
     true,
     6,
     kTheta,
     {0, 0.0029999999950000000, 1.4999999987500191e-7},
     {0, 0, 0},
     kExact},
    // EB0Z: -30 (sin b, 0, cos b - 1)
    {"EB0Z_FXYZ",
     "FXYZ",
     true,
     7,
     kTheta,
     {-0.0029999999950000000, 0, 1.4999999987500191e-7},
     {0, 0, 0},
     kExact},
    {"EB0Z_XYZF",
     "XYZF",
     true,
     7,
     kTheta,
     {-0.0029999999950000000, 0, 1.4999999987500191e-7},
     {0, 0, 0},
     kExact},
    // EC0Z: Rz(c) e_z = e_z -> 0
    {"EC0Z_FXYZ", "FXYZ", true, 8, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
    {"EC0Z_XYZF", "XYZF", true, 8, kTheta, {0, 0, 0}, {0, 0, 0}, kExact},
};

class Component : public ::testing::TestWithParam<ComponentCase> {};

TEST_P(Component, MatchesHandDerivation) {
  const ComponentCase& c = GetParam();
  MachineModelSpec spec;
  spec.topology = c.topology;
  spec.toolMm = Eigen::Vector3d(10, 20, 100);
  if (c.location) {
    spec.locationRad[c.index] = c.value;
  } else {
    spec.motion[c.index] = c.value;
  }
  const MachineModel model(spec);
  Workspace ws;
  const Eigen::Vector3d q(200, 50, -30);
  for (const EvalMode mode : {EvalMode::Exact, EvalMode::FirstOrder}) {
    const PointError e = evaluate(model, ws, q, {}, mode);
    // p - p0 is formed from positions of a few 100 mm: allow a few of their ulps.
    const double tolerance = c.tolerance + 2e-13;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(e.errorMm[i], c.error[i], tolerance) << "component " << i;
    }
    // A single rotation's angular error is exactly its angle (both modes).
    EXPECT_LT((e.angularErrorRad - c.angular).norm(), 1e-18);
  }
  // The reference composition gives the same (it forms p - p0 from the same positions).
  const PointError reference = evaluateReference(model, q);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(reference.errorMm[i], c.error[i], c.tolerance + 2e-13) << "reference " << i;
  }
  EXPECT_LT((reference.angularErrorRad - c.angular).norm(), 1e-18);
  // And the compensation offset puts the tool on the nominal point.
  const OffsetSolution o = solveOffset(model, ws, q);
  EXPECT_TRUE(o.converged);
  const PointError at = evaluate(model, ws, q + o.offsetMm);
  EXPECT_LT((at.errorMm + o.offsetMm).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(HandDerived, Component, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<ComponentCase>& param) {
                           return std::string(param.param.name);
                         });

TEST(Component, AllTwentySevenCoveredInBothTopologies) {
  EXPECT_EQ(std::size(kCases), 54u);
}

}  // namespace
}  // namespace volcomp::model
