#pragma once
/// A programmed move in machine axis coordinates (mm): a rapid, a straight feed, or an arc / helix
/// / LinuxCNC spiral (start and end radius may differ slightly; the radius then changes linearly
/// with the angle, as LinuxCNC's motion planner does).
///
/// Parameter u in [0, 1]: proportional to length for straight moves, to the angle for arcs (so
/// to the length of a circular arc; a spiral's length differs from that by at most its radius
/// change).

#include <cstdint>

#include <Eigen/Core>

namespace volcomp::nc {

using Vec3 = Eigen::Vector3d;

enum class MoveKind : std::uint8_t { Rapid, Line, Arc };

/// Most full turns one arc or helix may make (G2/G3 P, ARC_FEED rotation): far more than any
/// real program, few enough that the turn count and the splitting stay within integers.
inline constexpr int kMaxArcTurns = 10000;

/// Largest |position| (mm, each axis, machine coordinates or a program's frame) a move may reach:
/// no machine travels a kilometre; beyond it a position is a wrong offset or unit, and printed
/// counts (position x 10^decimals) or sample counts would no longer be exact integers.
inline constexpr double kMaxPositionMm = 1e6;

/// Arc geometry in machine coordinates. The plane is spanned by axes `first` and `second` (X, Y
/// for G17; Z, X for G18; Y, Z for G19, as LinuxCNC's canonical ARC_FEED orders them); `normal` is
/// the third axis. Angles are measured from `first` towards `second`; a positive sweep is
/// counter-clockwise in that sense.
struct ArcGeometry {
  int first = 0;
  int second = 1;
  int normal = 2;
  double centerFirst = 0.0;   ///< mm
  double centerSecond = 0.0;  ///< mm
  double startAngle = 0.0;    ///< rad
  double sweep = 0.0;         ///< rad, signed, may exceed 2 pi (several turns)
  double startRadius = 0.0;   ///< mm
  double endRadius = 0.0;     ///< mm
  double startNormal = 0.0;   ///< mm, along the normal axis
  double endNormal = 0.0;     ///< mm
};

struct Move {
  MoveKind kind = MoveKind::Line;
  Vec3 startMm = Vec3::Zero();
  Vec3 endMm = Vec3::Zero();
  ArcGeometry arc;

  /// Position at u in [0, 1] (exactly startMm at 0 and endMm at 1 for straight moves).
  Vec3 at(double u) const noexcept;
  /// Length of the move (arc: of the helix through the mean radius), mm.
  double lengthMm() const noexcept;
};

/// Arc geometry from its start point, end point and centre (plane coordinates: first, second)
/// and the LinuxCNC rotation count (canonical ARC_FEED; G2 = -P, G3 = +P): |rotation| - 1 extra
/// full turns; a start point equal to the end point (within 1e-9 of the radius) makes a full
/// circle. Positions in mm; `plane` 0 = XY, 1 = XZ, 2 = YZ.
ArcGeometry makeArc(int plane, const Vec3& startMm, const Vec3& endMm, double centerFirst,
                    double centerSecond, int rotation) noexcept;

}  // namespace volcomp::nc
