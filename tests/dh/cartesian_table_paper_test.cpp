// Bulla Ramos et al. (2018): the D-H chain of its table 1 with the perpendicularity
// deviations of section 2.2 must reproduce the paper's eq. 11 (symbolic T_e), eq. 12 (numbers)
// and eq. 13 (T_e - T).
//
// Reading table 1 and eqs. 6-10 as standard D-H links A_i = Rz(theta) Tz(d) Tx(a) Rx(alpha):
//   link 1: theta 0,  alpha 90                      -> eq. 6  [1 0 0 a1; 0 0 -1 0; 0 1 0 d1]
//   link 2: theta 90, alpha_2e = -90 - 0.00013544    -> eq. 7  [0 -Ca Sa 0; 1 0 0 a2; 0 Sa Ca d2]
//   link 3: theta 0,  alpha_3e = 0 + 0.0010835       -> eq. 8  [1 0 0 a3; 0 Ca -Sa 0; 0 Sa Ca d3]
//   M     : Ry(theta_e2), theta_e2 = 0.0010835       -> eq. 10 [Ct 0 St 0; 0 1 0 0; -St 0 Ct 0]
//   link 4: theta 0,  alpha 0                        -> eq. 9  [1 0 0 a4; 0 1 0 0; 0 0 1 d4]
// (all angles in degrees; the deviations are the paper's alpha_e1 = 0.00013544 deg subtracted
// from alpha_2 by eq. 3, and alpha_e2 = theta_e2 = 0.0010835 deg). M is a fixed transform with
// zero nominal and a deviation rotation about Y, placed between links 3 and 4 as in eq. 11,
// T_e = A1 A2 A3 M A4. The nominal T has alpha_2 = -90, alpha_3 = 0 and M = I.
//
// The table is a three-axis Cartesian table: links 1-3 are the prismatic X, Y, Z joints (their
// variables add to d1, d2, d3) and link 4 is the fixed torch (d4 its length, a4 its offset). This
// matches the paper's remark that the errors depend on d3 and d4 only (eq. 13). The lengths below
// are our choice (the paper leaves them symbolic); the same chain is in
// config/examples/cartesian-table-dh.json.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "volcomp/model/dh_chain.hpp"

namespace {

using volcomp::model::DhChain;
using volcomp::model::DhChainSpec;
using volcomp::model::DhLinkSpec;
using volcomp::model::JointType;

constexpr double kDeg = std::numbers::pi / 180.0;

// Lengths (mm).
constexpr double kA1 = 120.0, kD1 = 0.0;
constexpr double kA2 = 85.0, kD2 = 0.0;
constexpr double kA3 = 40.0, kD3 = 50.0;
constexpr double kA4 = 30.0, kD4 = 150.0;
// Deviations (deg).
constexpr double kAlphaE1Deg = 0.00013544;  // eq. 3-4: alpha_2real = -90 - alpha_e1
constexpr double kAlphaE2Deg = 0.0010835;   // alpha_3e and theta_e2 of M

DhLinkSpec dhLink(JointType joint, double thetaDeg, double dMm, double aMm, double alphaDeg,
                  double dAlphaDeg = 0.0) {
  DhLinkSpec link;
  link.joint = joint;
  link.thetaRad = thetaDeg * kDeg;
  link.dMm = dMm;
  link.aMm = aMm;
  link.alphaRad = alphaDeg * kDeg;
  link.dAlphaRad = dAlphaDeg * kDeg;
  return link;
}

DhChainSpec paperChain() {
  DhChainSpec spec;
  spec.name = "Cartesian table of Bulla Ramos et al.";
  spec.links.push_back(dhLink(JointType::Prismatic, 0.0, kD1, kA1, 90.0));
  spec.links.push_back(dhLink(JointType::Prismatic, 90.0, kD2, kA2, -90.0, -kAlphaE1Deg));
  spec.links.push_back(dhLink(JointType::Prismatic, 0.0, kD3, kA3, 0.0, kAlphaE2Deg));
  DhLinkSpec m;
  m.joint = JointType::Fixed;
  m.isTransform = true;
  m.dRotationRad = {0.0, kAlphaE2Deg * kDeg, 0.0};
  spec.links.push_back(m);
  spec.links.push_back(dhLink(JointType::Fixed, 0.0, kD4, kA4, 0.0));
  return spec;
}

// Joint values (mm) of the X, Y, Z axes; d_i = nominal d_i + joint value.
constexpr double kJoints[3] = {600.0, 400.0, 80.0};
constexpr double d1 = kD1 + kJoints[0], d2 = kD2 + kJoints[1], d3 = kD3 + kJoints[2], d4 = kD4;
constexpr double a1 = kA1, a2 = kA2, a3 = kA3, a4 = kA4;

TEST(CartesianTablePaper, ChainHasThreeJoints) {
  const DhChain chain(paperChain());
  EXPECT_EQ(chain.jointCount(), 3);
}

// Eq. 12 as printed (decimal commas read as points). Each printed entry agrees with the exact
// value to better than 1e-10 (the least precise, 0.99999999982 for cos(theta_e2) =
// 0.9999999998212, is off by 1.2e-12), so 1e-10 is the paper's own precision.
TEST(CartesianTablePaper, RotationOfActualMatchesEquation12) {
  const DhChain chain(paperChain());
  const auto result = chain.evaluate(kJoints);
  const double eq12[3][3] = {
      {1.891064e-5, -1.6546768e-5, -0.999999999684296},
      {3.129100e-10, 0.9999999998631, -1.65467685e-5},
      {0.99999999982, 0.0, 0.00001891064},
  };
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(result.tActual(r, c), eq12[r][c], 1e-10) << "T_actual(" << r << "," << c << ")";
    }
  }
  EXPECT_EQ(result.tActual.row(3), Eigen::RowVector4d(0, 0, 0, 1));
}

// Eq. 11 (the paper's symbolic product A1 A2 A3 M A4), written with beta = alpha_2e + alpha_3e
// (its sums of products are sin/cos of beta: S2 C3 + C2 S3 = S(beta), C2 C3 - S2 S3 = C(beta)):
//   R = [-St Sb, -Cb, Ct Sb; St Cb, -Sb, -Ct Cb; Ct, 0, St]
//   x = a1 - a4 St Sb + d4 Ct Sb + d3 S2
//   y = a4 St Cb - d4 Ct Cb - d2 - d3 C2
//   z = a4 Ct + d4 St + a2 + a3 + d1
// We checked it by hand: R1 R2 = Rx(90) Rz(90) = [0 -1 0; 0 0 -1; 1 0 0] maps (u, v, w) to
// (-v, -w, u); Rx(beta) Ry(theta) (a4, 0, d4) = (u, -Sb w, Cb w) with u = Ct a4 + St d4,
// w = -St a4 + Ct d4; R1 R2 A3's translation (a3, 0, d3) gives (S2 d3, -C2 d3, a3);
// R1 A2's translation gives (0, -d2, a2). Summing with (a1, 0, d1) gives the column above.
TEST(CartesianTablePaper, ActualMatchesEquation11Symbolically) {
  const DhChain chain(paperChain());
  const auto result = chain.evaluate(kJoints);
  const double alpha2 = (-90.0 - kAlphaE1Deg) * kDeg, alpha3 = kAlphaE2Deg * kDeg;
  const double beta = alpha2 + alpha3, theta = kAlphaE2Deg * kDeg;
  const double sb = std::sin(beta), cb = std::cos(beta), st = std::sin(theta), ct = std::cos(theta);
  const double s2 = std::sin(alpha2), c2 = std::cos(alpha2);
  Eigen::Matrix4d eq11;
  eq11 << -st * sb, -cb, ct * sb, a1 - a4 * st * sb + d4 * ct * sb + d3 * s2,  //
      st * cb, -sb, -ct * cb, a4 * st * cb - d4 * ct * cb - d2 - d3 * c2,      //
      ct, 0.0, st, a4 * ct + d4 * st + a2 + a3 + d1,                           //
      0.0, 0.0, 0.0, 1.0;
  // Rounding only: entries of size <= 1000 mm carry ~1e-13 mm of double rounding.
  EXPECT_LT((result.tActual - eq11).cwiseAbs().maxCoeff(), 1e-11);
}

// Nominal (alpha_2 = -90, alpha_3 = 0, M = I): eq. 11 with beta = -90, theta = 0, S2 = -1,
// C2 = 0: R = [0 0 -1; 0 1 0; 1 0 0], p = (a1 - d4 - d3, -d2, a4 + a2 + a3 + d1).
TEST(CartesianTablePaper, NominalIsTheIdealTable) {
  const DhChain chain(paperChain());
  const auto result = chain.evaluate(kJoints);
  Eigen::Matrix4d expected;
  expected << 0, 0, -1, a1 - d4 - d3,  //
      0, 1, 0, -d2,                    //
      1, 0, 0, a4 + a2 + a3 + d1,      //
      0, 0, 0, 1;
  EXPECT_LT((result.tNominal - expected).cwiseAbs().maxCoeff(), 1e-12);
}

// Eq. 13's last column (the position error), with the paper's printed coefficients:
//   ex = 1.891e-5 a4 + 4e-10 d4 + 3e-10 d3
//   ey = 3.1291e-10 a4 - 1.65468e-5 d4 + 2.36387e-6 d3
//   ez = -2e-10 a4 + 1.891e-5 d4
// (eq. 11 minus the nominal column). The paper rounds these: exactly, ex's d4 coefficient is
// 1 + Ct Sb = 3.157e-10 and its d3 coefficient 1 + S2 = 2.8e-12 (printed 3e-10 from the
// truncated 0.99999999972), ex's a4 coefficient -St Sb = 1.8910643e-5, ez's a4 coefficient
// Ct - 1 = -1.788e-10. With a4 = 30, d4 = 150,
// d3 = 130 mm the rounding amounts to < 7e-8 mm in ex and < 1e-8 mm in ey, ez: tolerance 1e-7 mm.
// The errors themselves are ~0.6 um (ex), -2.2 um (ey) and 2.8 um (ez).
TEST(CartesianTablePaper, ErrorColumnMatchesEquation13) {
  const DhChain chain(paperChain());
  const auto result = chain.evaluate(kJoints);
  const Eigen::Vector3d eq13(1.891e-5 * a4 + 4e-10 * d4 + 3e-10 * d3,
                             3.1291e-10 * a4 - 1.65468e-5 * d4 + 2.36387e-6 * d3,
                             -2e-10 * a4 + 1.891e-5 * d4);
  EXPECT_LT((result.errorMm - eq13).cwiseAbs().maxCoeff(), 1e-7)
      << "error " << result.errorMm.transpose() << " eq13 " << eq13.transpose();
  // The error column is exactly T_actual - T_nominal's.
  EXPECT_EQ(result.errorMm, Eigen::Vector3d(result.tActual.topRightCorner<3, 1>() -
                                            result.tNominal.topRightCorner<3, 1>()));
}

// R_nominal^T R_actual: the first three links' rotations are identical but for alpha, and
// Rx(a) Rx(b) = Rx(a + b), so R_nominal^T R_actual = Rx(delta) Ry(theta_e2) with
// delta = alpha_e2 - alpha_e1 = 0.00094806 deg. Its rotation vector (BCH to second order) is
// (delta, theta_e2, delta theta_e2 / 2): third-order terms are ~1e-14 rad.
TEST(CartesianTablePaper, AngularErrorIsTheTwoPerpendicularityDeviations) {
  const DhChain chain(paperChain());
  const auto result = chain.evaluate(kJoints);
  const double delta = (kAlphaE2Deg - kAlphaE1Deg) * kDeg, theta = kAlphaE2Deg * kDeg;
  EXPECT_NEAR(result.angularErrorRad.x(), delta, 1e-13);
  EXPECT_NEAR(result.angularErrorRad.y(), theta, 1e-13);
  EXPECT_NEAR(result.angularErrorRad.z(), delta * theta / 2.0, 1e-13);
}

}  // namespace
