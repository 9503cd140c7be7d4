#include "volcomp/model/so3.hpp"

#include <cmath>
#include <numbers>

#include "small_angle.hpp"

namespace volcomp::model {

Eigen::Matrix3d rotationZYX(double aRad, double bRad, double cRad) noexcept {
  return detail::rotationZYXMinusIdentity(aRad, bRad, cRad) + Eigen::Matrix3d::Identity();
}

Eigen::Vector3d rotationVector(const Eigen::Matrix3d& r) noexcept {
  // R = I + sin(t) K + (1 - cos(t)) K^2 for the unit axis k (K its cross-product matrix):
  // the skew part gives s = sin(t) k, the trace gives cos(t).
  const Eigen::Vector3d s(0.5 * (r(2, 1) - r(1, 2)), 0.5 * (r(0, 2) - r(2, 0)),
                          0.5 * (r(1, 0) - r(0, 1)));
  const double cosAngle = 0.5 * (r.trace() - 1.0);
  const double s2 = s.squaredNorm();
  if (cosAngle > 0.0 && s2 < 1e-4) {
    // t / sin(t) = asin(x) / x with x = sin(t) = |s|: 1 + x^2/6 + 3x^4/40 + 5x^6/112 + 35x^8/1152;
    // for x < 1e-2 the omitted terms are below 1e-19 relative, and no acos is needed.
    const double f =
        1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0 + s2 * (5.0 / 112.0 + s2 * (35.0 / 1152.0))));
    return f * s;
  }
  const double sinAngle = std::sqrt(s2);
  const double angle = std::atan2(sinAngle, cosAngle);
  if (angle < std::numbers::pi - 1e-3) {
    return (angle / sinAngle) * s;
  }
  // Near pi the skew part vanishes; take the axis from the symmetric part,
  // (R + R^T) / 2 = cos(t) I + (1 - cos(t)) k k^T, using its largest diagonal column.
  const Eigen::Matrix3d kkT =
      (0.5 * (r + r.transpose()) - cosAngle * Eigen::Matrix3d::Identity()) / (1.0 - cosAngle);
  int column = 0;
  if (kkT(1, 1) > kkT(column, column)) column = 1;
  if (kkT(2, 2) > kkT(column, column)) column = 2;
  Eigen::Vector3d axis = kkT.col(column) / std::sqrt(kkT(column, column));
  axis.normalize();
  // The sign of the axis is only defined by the (small) skew part; at exactly pi both are valid.
  if (axis.dot(s) < 0.0) axis = -axis;
  return angle * axis;
}

}  // namespace volcomp::model
