#include "volcomp/nc/move.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace volcomp::nc {

Vec3 Move::at(double u) const noexcept {
  if (kind != MoveKind::Arc) {
    if (u <= 0.0) return startMm;
    if (u >= 1.0) return endMm;
    return startMm + u * (endMm - startMm);
  }
  if (u <= 0.0) return startMm;
  if (u >= 1.0) return endMm;
  const ArcGeometry& a = arc;
  const double angle = a.startAngle + u * a.sweep;
  const double radius = a.startRadius + u * (a.endRadius - a.startRadius);
  Vec3 p;
  p[a.first] = a.centerFirst + radius * std::cos(angle);
  p[a.second] = a.centerSecond + radius * std::sin(angle);
  p[a.normal] = a.startNormal + u * (a.endNormal - a.startNormal);
  return p;
}

double Move::lengthMm() const noexcept {
  if (kind != MoveKind::Arc) return (endMm - startMm).norm();
  const double radius = 0.5 * (arc.startRadius + arc.endRadius);
  return std::hypot(radius * arc.sweep, arc.endNormal - arc.startNormal);
}

ArcGeometry makeArc(int plane, const Vec3& startMm, const Vec3& endMm, double centerFirst,
                    double centerSecond, int rotation) noexcept {
  static constexpr int kAxes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
  ArcGeometry a;
  a.first = kAxes[plane][0];
  a.second = kAxes[plane][1];
  a.normal = kAxes[plane][2];
  a.centerFirst = centerFirst;
  a.centerSecond = centerSecond;
  const double s1 = startMm[a.first] - centerFirst;
  const double s2 = startMm[a.second] - centerSecond;
  const double e1 = endMm[a.first] - centerFirst;
  const double e2 = endMm[a.second] - centerSecond;
  a.startRadius = std::hypot(s1, s2);
  a.endRadius = std::hypot(e1, e2);
  a.startAngle = std::atan2(s2, s1);
  a.startNormal = startMm[a.normal];
  a.endNormal = endMm[a.normal];
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const bool fullCircle = std::hypot(e1 - s1, e2 - s2) <= 1e-9 * std::max(1.0, a.startRadius);
  double sweep = std::atan2(e2, e1) - a.startAngle;
  const int turns = rotation == 0 ? 1 : std::abs(rotation);
  if (rotation >= 0) {
    while (sweep <= 0.0) sweep += kTwoPi;
    if (fullCircle) sweep = kTwoPi;
    sweep += kTwoPi * (turns - 1);
  } else {
    while (sweep >= 0.0) sweep -= kTwoPi;
    if (fullCircle) sweep = -kTwoPi;
    sweep -= kTwoPi * (turns - 1);
  }
  a.sweep = sweep;
  return a;
}

}  // namespace volcomp::nc
