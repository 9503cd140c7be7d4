#pragma once
// sin, cos and cos - 1 that are exact to double precision but cheap for the small angles of error
// motions, and Rz Ry Rx - I formed without cancellation.

#include <cmath>

#include <Eigen/Core>

namespace volcomp::model::detail {

// Below this |angle| the truncated Taylor series are exact to double rounding: the first omitted
// terms are x^9/9! (sin) and x^8/8! (cos - 1), below 3e-21 relative at 1e-2 rad.
inline constexpr double kSmallAngleRad = 1e-2;

/// s = sin(x), m = cos(x) - 1 (full relative precision also for tiny x).
inline void sinCosm1(double x, double& s, double& m) noexcept {
  if (std::abs(x) < kSmallAngleRad) {
    // Multiplications by the reciprocal factorials: a division would cost 15-20 cycles each.
    const double x2 = x * x;
    s = x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040)));
    m = x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720)));
  } else {
    s = std::sin(x);
    const double h = std::sin(0.5 * x);
    m = -2.0 * h * h;
  }
}

/// Rz(c) Ry(b) Rx(a) - I. Its diagonal is formed from cos - 1 directly, so that a rotation of
/// 1e-4 rad keeps 16 digits in R - I (R itself would round its 1 - 5e-9 diagonal to 1e-16
/// absolute, i.e. 1e-13 mm on a 1 m arm).
inline Eigen::Matrix3d rotationZYXMinusIdentity(double a, double b, double c) noexcept {
  double sa, ma, sb, mb, sc, mc;
  sinCosm1(a, sa, ma);
  sinCosm1(b, sb, mb);
  sinCosm1(c, sc, mc);
  const double ca = 1.0 + ma, cb = 1.0 + mb, cc = 1.0 + mc;
  Eigen::Matrix3d r;
  r(0, 0) = mc + mb + mc * mb;  // cc cb - 1
  r(0, 1) = cc * sb * sa - sc * ca;
  r(0, 2) = cc * sb * ca + sc * sa;
  r(1, 0) = sc * cb;
  r(1, 1) = sc * sb * sa + mc + ma + mc * ma;  // sc sb sa + cc ca - 1
  r(1, 2) = sc * sb * ca - cc * sa;
  r(2, 0) = -sb;
  r(2, 1) = cb * sa;
  r(2, 2) = mb + ma + mb * ma;  // cb ca - 1
  return r;
}

}  // namespace volcomp::model::detail
