#include "volcomp/model/dh_chain.hpp"

#include <cmath>
#include <string>
#include <utility>

#include "volcomp/model/so3.hpp"

namespace volcomp::model {
namespace {

// Closed forms rather than products of elementary matrices: fewer flops, and the zeros of the
// elementary rotations stay exact zeros in the result.

// Rz(theta) Trans(0,0,d) Trans(a,0,0) Rx(alpha) (Bulla Ramos et al., eq. 1).
Eigen::Matrix4d standardLink(double thetaRad, double dMm, double aMm, double alphaRad) noexcept {
  const double ct = std::cos(thetaRad), st = std::sin(thetaRad);
  const double ca = std::cos(alphaRad), sa = std::sin(alphaRad);
  Eigen::Matrix4d m;
  m << ct, -ca * st, sa * st, aMm * ct,  //
      st, ca * ct, -sa * ct, aMm * st,   //
      0.0, sa, ca, dMm,                  //
      0.0, 0.0, 0.0, 1.0;
  return m;
}

// Rx(alpha) Trans(a,0,0) Rz(theta) Trans(0,0,d) (Craig).
Eigen::Matrix4d modifiedLink(double thetaRad, double dMm, double aMm, double alphaRad) noexcept {
  const double ct = std::cos(thetaRad), st = std::sin(thetaRad);
  const double ca = std::cos(alphaRad), sa = std::sin(alphaRad);
  Eigen::Matrix4d m;
  m << ct, -st, 0.0, aMm,                //
      ca * st, ca * ct, -sa, -sa * dMm,  //
      sa * st, sa * ct, ca, ca * dMm,    //
      0.0, 0.0, 0.0, 1.0;
  return m;
}

// Trans(t) Rz(r.z) Ry(r.y) Rx(r.x).
Eigen::Matrix4d fixedTransform(const Eigen::Vector3d& rotationRad,
                               const Eigen::Vector3d& translationMm) noexcept {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotationZYX(rotationRad.x(), rotationRad.y(), rotationRad.z());
  m.topRightCorner<3, 1>() = translationMm;
  return m;
}

// One link's transform; `withDeviations` selects actual (true) or nominal (false) parameters.
Eigen::Matrix4d linkTransform(const DhLinkSpec& link, DhConvention convention, double jointValue,
                              bool withDeviations) noexcept {
  if (link.isTransform) {
    if (!withDeviations) return fixedTransform(link.rotationRad, link.translationMm);
    return fixedTransform(link.rotationRad + link.dRotationRad,
                          link.translationMm + link.dTranslationMm);
  }
  const double k = withDeviations ? 1.0 : 0.0;
  double theta = link.thetaRad + k * link.dThetaRad;
  double d = link.dMm + k * link.dDMm;
  const double a = link.aMm + k * link.dAMm;
  const double alpha = link.alphaRad + k * link.dAlphaRad;
  if (link.joint == JointType::Prismatic) d += jointValue;
  if (link.joint == JointType::Revolute) theta += jointValue;
  return convention == DhConvention::Standard ? standardLink(theta, d, a, alpha)
                                              : modifiedLink(theta, d, a, alpha);
}

bool allFinite(const DhLinkSpec& link) {
  const double scalars[] = {link.thetaRad,  link.dMm,  link.aMm,  link.alphaRad,
                            link.dThetaRad, link.dDMm, link.dAMm, link.dAlphaRad};
  for (double v : scalars) {
    if (!std::isfinite(v)) return false;
  }
  return link.rotationRad.allFinite() && link.translationMm.allFinite() &&
         link.dRotationRad.allFinite() && link.dTranslationMm.allFinite();
}

}  // namespace

DhChain::DhChain(DhChainSpec spec) : spec_(std::move(spec)) {
  const std::string where = spec_.name.empty() ? "D-H chain" : "D-H chain '" + spec_.name + "'";
  if (spec_.links.empty()) throw ModelError(where + ": the chain has no links");
  for (std::size_t i = 0; i < spec_.links.size(); ++i) {
    const DhLinkSpec& link = spec_.links[i];
    const std::string at = where + ": link " + std::to_string(i + 1);
    if (!allFinite(link)) throw ModelError(at + ": parameters must be finite numbers");
    if (link.isTransform && link.joint != JointType::Fixed) {
      throw ModelError(at + ": a fixed transform (rotation + translation) cannot be a joint");
    }
    if (link.joint != JointType::Fixed) ++jointCount_;
  }
}

DhResult DhChain::evaluate(const double* jointValues) const noexcept {
  DhResult result;
  int joint = 0;
  for (const DhLinkSpec& link : spec_.links) {
    const double q = link.joint == JointType::Fixed ? 0.0 : jointValues[joint++];
    result.tNominal *= linkTransform(link, spec_.convention, q, false);
    result.tActual *= linkTransform(link, spec_.convention, q, true);
  }
  result.errorMm = result.tActual.topRightCorner<3, 1>() - result.tNominal.topRightCorner<3, 1>();
  result.angularErrorRad = rotationVector(result.tNominal.topLeftCorner<3, 3>().transpose() *
                                          result.tActual.topLeftCorner<3, 3>());
  return result;
}

}  // namespace volcomp::model
