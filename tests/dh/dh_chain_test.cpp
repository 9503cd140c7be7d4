// DhChain (docs/model-file.md, "Denavit-Hartenberg chains"): conventions against hand-computed
// matrices, deviations, joint variables, validation and allocation-free evaluation.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "allocation_counter.hpp"
#include "volcomp/model/dh_chain.hpp"

namespace {

using volcomp::model::DhChain;
using volcomp::model::DhChainSpec;
using volcomp::model::DhConvention;
using volcomp::model::DhLinkSpec;
using volcomp::model::JointType;
using volcomp::model::ModelError;

constexpr double kDeg = std::numbers::pi / 180.0;

DhLinkSpec dhLink(JointType joint, double thetaRad, double dMm, double aMm, double alphaRad) {
  DhLinkSpec link;
  link.joint = joint;
  link.thetaRad = thetaRad;
  link.dMm = dMm;
  link.aMm = aMm;
  link.alphaRad = alphaRad;
  return link;
}

DhLinkSpec transformLink(const Eigen::Vector3d& rotationRad, const Eigen::Vector3d& translationMm) {
  DhLinkSpec link;
  link.isTransform = true;
  link.rotationRad = rotationRad;
  link.translationMm = translationMm;
  return link;
}

DhChainSpec chainOf(DhConvention convention, std::vector<DhLinkSpec> links) {
  DhChainSpec spec;
  spec.convention = convention;
  spec.links = std::move(links);
  return spec;
}

Eigen::Matrix4d rotX(double a) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return m;
}
Eigen::Matrix4d rotY(double a) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return m;
}
Eigen::Matrix4d rotZ(double a) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return m;
}
Eigen::Matrix4d trans(double x, double y, double z) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topRightCorner<3, 1>() = Eigen::Vector3d(x, y, z);
  return m;
}

double maxAbs(const Eigen::Matrix4d& m) {
  return m.cwiseAbs().maxCoeff();
}

// A mixed chain used by several tests: revolute, prismatic, fixed D-H, fixed transform,
// prismatic; generic angles so that no axis is aligned with another by accident.
std::vector<DhLinkSpec> mixedLinks() {
  std::vector<DhLinkSpec> links;
  links.push_back(dhLink(JointType::Revolute, 10 * kDeg, 200, 50, 90 * kDeg));
  links.push_back(dhLink(JointType::Prismatic, 35 * kDeg, 80, -20, -60 * kDeg));
  links.push_back(dhLink(JointType::Fixed, -15 * kDeg, 30, 120, 25 * kDeg));
  links.push_back(transformLink({5 * kDeg, -10 * kDeg, 20 * kDeg}, {15, -25, 40}));
  links.push_back(dhLink(JointType::Prismatic, 0, 10, 0, 0));
  return links;
}
constexpr double kMixedJoints[3] = {40 * kDeg, 120.0, 75.0};

// Standard: A1 = Rz(90) Tx(100) = [0 -1 0 0; 1 0 0 100; 0 0 1 0] (revolute, theta = 0 + q,
// q = 90 deg); A2 = Tz(20) Tx(50) Rx(90) = [1 0 0 50; 0 0 -1 0; 0 1 0 20].
// T = A1 A2: R = Rz(90) Rx(90) = [0 -1 0; 1 0 0; 0 0 1][1 0 0; 0 0 -1; 0 1 0] = [0 0 1; 1 0 0;
// 0 1 0]; p = (0, 100, 0) + Rz(90) (50, 0, 20) = (0, 100, 0) + (0, 50, 20) = (0, 150, 20).
TEST(DhChain, StandardTwoLinksMatchHandComputedMatrix) {
  const DhChain chain(chainOf(
      DhConvention::Standard,
      {dhLink(JointType::Revolute, 0, 0, 100, 0), dhLink(JointType::Fixed, 0, 20, 50, 90 * kDeg)}));
  const double q[] = {90 * kDeg};
  Eigen::Matrix4d expected;
  expected << 0, 0, 1, 0,  //
      1, 0, 0, 150,        //
      0, 1, 0, 20,         //
      0, 0, 0, 1;
  const auto result = chain.evaluate(q);
  EXPECT_LT(maxAbs(result.tNominal - expected), 1e-12) << result.tNominal;
  EXPECT_LT(maxAbs(result.tActual - expected), 1e-12);
}

// Modified, same parameters: A1 = Rx(0) Tx(100) Rz(90) Tz(0) = [0 -1 0 100; 1 0 0 0; 0 0 1 0];
// A2 = Rx(90) Tx(50) Rz(0) Tz(20) = [1 0 0 50; 0 0 -1 -20; 0 1 0 0] (Rx(90) (0, 0, 20) =
// (0, -20, 0)). T = A1 A2: R = Rz(90) Rx(90) = [0 0 1; 1 0 0; 0 1 0] as above;
// p = (100, 0, 0) + Rz(90) (50, -20, 0) = (100, 0, 0) + (20, 50, 0) = (120, 50, 0).
TEST(DhChain, ModifiedTwoLinksMatchHandComputedMatrix) {
  const DhChain chain(chainOf(
      DhConvention::Modified,
      {dhLink(JointType::Revolute, 0, 0, 100, 0), dhLink(JointType::Fixed, 0, 20, 50, 90 * kDeg)}));
  const double q[] = {90 * kDeg};
  Eigen::Matrix4d expected;
  expected << 0, 0, 1, 120,  //
      1, 0, 0, 50,           //
      0, 1, 0, 0,            //
      0, 0, 0, 1;
  EXPECT_LT(maxAbs(chain.evaluate(q).tNominal - expected), 1e-12);
}

// One link with generic parameters against the definition written as a product of elementary
// transforms (built independently with Eigen::AngleAxis).
TEST(DhChain, SingleLinkIsTheProductOfItsElementaryTransforms) {
  const double theta = 30 * kDeg, d = 12.5, a = -7.0, alpha = 45 * kDeg, q = 3.5;
  const DhLinkSpec link = dhLink(JointType::Prismatic, theta, d, a, alpha);
  const Eigen::Matrix4d standard = rotZ(theta) * trans(0, 0, d + q) * trans(a, 0, 0) * rotX(alpha);
  const Eigen::Matrix4d modified = rotX(alpha) * trans(a, 0, 0) * rotZ(theta) * trans(0, 0, d + q);
  const double joints[] = {q};
  EXPECT_LT(
      maxAbs(DhChain(chainOf(DhConvention::Standard, {link})).evaluate(joints).tNominal - standard),
      1e-13);
  EXPECT_LT(
      maxAbs(DhChain(chainOf(DhConvention::Modified, {link})).evaluate(joints).tNominal - modified),
      1e-13);
}

// Fixed transform: Trans(x,y,z) Rz(rz) Ry(ry) Rx(rx); its deviations add to the parameters.
TEST(DhChain, FixedTransformIsTransRzRyRxAndDeviationsAddToItsParameters) {
  DhLinkSpec link = transformLink({10 * kDeg, -20 * kDeg, 30 * kDeg}, {1, 2, 3});
  link.dRotationRad = {0.001, 0.002, -0.003};
  link.dTranslationMm = {0.01, -0.02, 0.03};
  const DhChain chain(chainOf(DhConvention::Standard, {link}));
  EXPECT_EQ(chain.jointCount(), 0);
  const auto result = chain.evaluate(nullptr);
  const Eigen::Matrix4d nominal =
      trans(1, 2, 3) * rotZ(30 * kDeg) * rotY(-20 * kDeg) * rotX(10 * kDeg);
  const Eigen::Matrix4d actual = trans(1.01, 1.98, 3.03) * rotZ(30 * kDeg - 0.003) *
                                 rotY(-20 * kDeg + 0.002) * rotX(10 * kDeg + 0.001);
  EXPECT_LT(maxAbs(result.tNominal - nominal), 1e-13);
  EXPECT_LT(maxAbs(result.tActual - actual), 1e-13);
  EXPECT_LT((result.errorMm - Eigen::Vector3d(0.01, -0.02, 0.03)).cwiseAbs().maxCoeff(), 1e-15);
}

// Planar 2R arm (alpha = 0, d = 0): p = (a1 c1 + a2 c12, a1 s1 + a2 s12, 0), R = Rz(q1 + q2).
// With nominal theta 10 deg and joint values 20, 45 deg: q1 = 30, q1 + q2 = 75 deg.
TEST(DhChain, RevoluteJointValuesAddToTheta) {
  const DhChain chain(
      chainOf(DhConvention::Standard, {dhLink(JointType::Revolute, 10 * kDeg, 0, 300, 0),
                                       dhLink(JointType::Revolute, 0, 0, 200, 0)}));
  EXPECT_EQ(chain.jointCount(), 2);
  const double q[] = {20 * kDeg, 45 * kDeg};
  const auto t = chain.evaluate(q).tNominal;
  const double c1 = std::cos(30 * kDeg), s1 = std::sin(30 * kDeg);
  const double c12 = std::cos(75 * kDeg), s12 = std::sin(75 * kDeg);
  EXPECT_NEAR(t(0, 3), 300 * c1 + 200 * c12, 1e-12);
  EXPECT_NEAR(t(1, 3), 300 * s1 + 200 * s12, 1e-12);
  EXPECT_NEAR(t(2, 3), 0.0, 1e-12);
  EXPECT_LT(maxAbs(t - trans(t(0, 3), t(1, 3), 0) * rotZ(75 * kDeg)), 1e-13);
}

// A joint's variable is the same thing as a fixed link whose theta (revolute) or d (prismatic)
// holds the value.
TEST(DhChain, JointVariableEqualsFixedLinkWithShiftedParameter) {
  for (const auto convention : {DhConvention::Standard, DhConvention::Modified}) {
    std::vector<DhLinkSpec> frozen = mixedLinks();
    frozen[0].joint = JointType::Fixed;
    frozen[0].thetaRad += kMixedJoints[0];
    frozen[1].joint = JointType::Fixed;
    frozen[1].dMm += kMixedJoints[1];
    frozen[4].joint = JointType::Fixed;
    frozen[4].dMm += kMixedJoints[2];
    const auto moving = DhChain(chainOf(convention, mixedLinks())).evaluate(kMixedJoints);
    const auto fixed = DhChain(chainOf(convention, frozen)).evaluate(nullptr);
    EXPECT_LT(maxAbs(moving.tNominal - fixed.tNominal), 1e-12);
  }
}

TEST(DhChain, ZeroDeviationsGiveZeroError) {
  for (const auto convention : {DhConvention::Standard, DhConvention::Modified}) {
    const DhChain chain(chainOf(convention, mixedLinks()));
    EXPECT_EQ(chain.jointCount(), 3);
    const auto result = chain.evaluate(kMixedJoints);
    EXPECT_EQ(result.tActual, result.tNominal);
    EXPECT_EQ(result.errorMm, Eigen::Vector3d::Zero());
    // R^T R is the identity only to rounding, so the log map may return ~1e-16.
    EXPECT_LT(result.angularErrorRad.norm(), 1e-14);
  }
}

// Standard D-H: d_k is a translation along z_{k-1}, the z axis of the frame after links
// 1..k-1, with nothing downstream changing orientation. So a deviation dd on link k moves the
// end point by dd z_{k-1} and leaves the orientation alone. (Modified: d_k is along z_k, the frame
// after link k itself.)
TEST(DhChain, PrismaticDdShiftsAlongThatJointsAxis) {
  const double dd = 0.025;
  for (const auto convention : {DhConvention::Standard, DhConvention::Modified}) {
    std::vector<DhLinkSpec> links = mixedLinks();
    links[1].dDMm = dd;
    const auto result = DhChain(chainOf(convention, links)).evaluate(kMixedJoints);
    const std::size_t prefixLength = convention == DhConvention::Standard ? 1 : 2;
    const std::vector<DhLinkSpec> prefix(links.begin(),
                                         links.begin() + static_cast<long>(prefixLength));
    const Eigen::Matrix4d framePrefix =
        DhChain(chainOf(convention, prefix)).evaluate(kMixedJoints).tNominal;
    const Eigen::Vector3d jointAxis = framePrefix.block<3, 1>(0, 2);
    EXPECT_LT((result.errorMm - dd * jointAxis).cwiseAbs().maxCoeff(), 1e-13)
        << result.errorMm.transpose() << " vs " << (dd * jointAxis).transpose();
    EXPECT_LT(result.angularErrorRad.norm(), 1e-14);
  }
}

// Standard D-H: theta_k is a rotation about z_{k-1} through o_{k-1} (the frame after links
// 1..k-1). A deviation dtheta therefore rotates everything downstream: p_actual = o + R(z,
// dtheta) (p_nominal - o) and R_actual = R(z, dtheta) R_nominal, hence R_nominal^T R_actual =
// R(R_nominal^T z, dtheta), whose rotation vector is dtheta R_nominal^T z.
TEST(DhChain, RevoluteDthetaRotatesDownstreamAboutTheJointAxis) {
  const double dtheta = 2e-4;
  std::vector<DhLinkSpec> links = mixedLinks();
  links[1].dThetaRad = dtheta;  // link 2 (prismatic) has a theta too; its axis is z_1
  const auto result = DhChain(chainOf(DhConvention::Standard, links)).evaluate(kMixedJoints);
  const Eigen::Matrix4d frame1 =
      DhChain(chainOf(DhConvention::Standard, {links[0]})).evaluate(kMixedJoints).tNominal;
  const Eigen::Vector3d origin = frame1.block<3, 1>(0, 3), axis = frame1.block<3, 1>(0, 2);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(dtheta, axis).toRotationMatrix();
  const Eigen::Vector3d pNominal = result.tNominal.block<3, 1>(0, 3);
  const Eigen::Vector3d pActual = origin + turn * (pNominal - origin);
  EXPECT_LT((result.tActual.block<3, 1>(0, 3) - pActual).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((result.errorMm - (pActual - pNominal)).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::Vector3d expectedAngular =
      dtheta * (result.tNominal.topLeftCorner<3, 3>().transpose() * axis);
  EXPECT_LT((result.angularErrorRad - expectedAngular).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(DhChain, RejectsEmptyChain) {
  EXPECT_THROW(DhChain(DhChainSpec{}), ModelError);
}

TEST(DhChain, RejectsNonFiniteParameters) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<DhLinkSpec> links = mixedLinks();
  links[2].dDMm = nan;
  EXPECT_THROW(DhChain(chainOf(DhConvention::Standard, links)), ModelError);
  links = mixedLinks();
  links[0].alphaRad = inf;
  EXPECT_THROW(DhChain(chainOf(DhConvention::Standard, links)), ModelError);
  links = mixedLinks();
  links[3].dTranslationMm.y() = -inf;
  EXPECT_THROW(DhChain(chainOf(DhConvention::Modified, links)), ModelError);
  links = mixedLinks();
  links[3].rotationRad.z() = nan;
  EXPECT_THROW(DhChain(chainOf(DhConvention::Modified, links)), ModelError);
}

TEST(DhChain, RejectsFixedTransformDeclaredAsJoint) {
  std::vector<DhLinkSpec> links = mixedLinks();
  links[3].joint = JointType::Prismatic;
  EXPECT_THROW(DhChain(chainOf(DhConvention::Standard, links)), ModelError);
}

TEST(DhChain, ErrorMessageNamesTheLink) {
  std::vector<DhLinkSpec> links = mixedLinks();
  links[2].aMm = std::numeric_limits<double>::quiet_NaN();
  DhChainSpec spec = chainOf(DhConvention::Standard, links);
  spec.name = "demo";
  try {
    const DhChain chain(spec);
    FAIL() << "expected ModelError";
  } catch (const ModelError& error) {
    EXPECT_NE(std::string(error.what()).find("'demo': link 3"), std::string::npos) << error.what();
  }
}

TEST(DhChain, EvaluateDoesNotAllocate) {
  std::vector<DhLinkSpec> links = mixedLinks();
  links[0].dThetaRad = 1e-4;
  links[3].dRotationRad = {1e-5, 2e-5, -3e-5};
  const DhChain standard(chainOf(DhConvention::Standard, links));
  const DhChain modified(chainOf(DhConvention::Modified, links));
  // The counter must see an ordinary allocation, or the check below proves nothing.
  const auto beforeVector = volcomp::testutil::allocationCount();
  {
    std::vector<double> probe(1000, 1.0);
    EXPECT_EQ(probe.size(), 1000u);
  }
  EXPECT_GT(volcomp::testutil::allocationCount(), beforeVector);

  double sum = 0.0;
  const auto before = volcomp::testutil::allocationCount();
  for (int i = 0; i < 100; ++i) {
    const double q[] = {i * kDeg, 100.0 + i, 50.0 - i};
    sum += standard.evaluate(q).errorMm.sum() + modified.evaluate(q).angularErrorRad.sum();
  }
  EXPECT_EQ(volcomp::testutil::allocationCount(), before);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
