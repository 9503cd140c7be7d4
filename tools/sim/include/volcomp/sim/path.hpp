#pragma once
/// The programmed tool path of the simulated machine: a closed loop travelled at a constant feed,
/// so that the programmed position is a pure function of the path time. Positions in mm (machine
/// axes X, Y, Z), feed in mm/min, time in s.

#include <array>
#include <string>
#include <vector>

namespace volcomp::sim {

using Vec3 = std::array<double, 3>;

class Path {
 public:
  /// Straight segments through `points`, back to the first point, then again.
  static Path polyline(std::vector<Vec3> points, double feedMmMin);
  /// Zig-zag lines along X from `from` to `to`, stepping Y by `stepMm`; with from.z != to.z the
  /// pattern repeats on Z levels `stepMm` apart. Closed by a straight return to the start.
  static Path raster(const Vec3& from, const Vec3& to, double stepMm, double feedMmMin);
  /// Circle in the XY plane around `center` (at center.z), counter-clockwise from +X.
  static Path circle(const Vec3& center, double radiusMm, double feedMmMin);
  /// Points from a CSV file read with config::CsvReader: a header with x,y,z (mm, or a unit
  /// suffix such as x_um; any order; `#` comments), one row per point. Throws config::ConfigError
  /// (a std::runtime_error) naming the file, line and column.
  static Path fromCsv(const std::string& file, double feedMmMin);
  /// The same polyline driven as a CNC in exact stop drives it: every segment starts and ends at
  /// rest, accelerating and braking at `accelMmS2` (mm/s^2, along the path) around a cruise at the
  /// feed, or braking at once where the segment is too short to reach the feed. A reversal is
  /// then a constant deceleration through zero velocity, as on a real machine, not a jump of the
  /// velocity. Throws std::invalid_argument for a circle or a non-positive acceleration.
  Path withAcceleration(double accelMmS2) const;

  /// Programmed position after `pathTimeS` seconds of motion (the path repeats).
  Vec3 at(double pathTimeS) const noexcept;
  double lengthMm() const noexcept { return lengthMm_; }
  double feedMmMin() const noexcept { return feedMmMin_; }
  /// Axis-aligned bounds of the path, mm.
  std::array<Vec3, 2> bounds() const noexcept;

 private:
  enum class Kind { Polyline, Circle };
  Kind kind_ = Kind::Polyline;
  std::vector<Vec3> points_;   // polyline vertices, closed (last = first)
  std::vector<double> cumMm_;  // arc length at each vertex
  double accelMmS2_ = 0.0;     // 0: constant feed, corners taken without braking
  std::vector<double> cumS_;   // with accelMmS2_: path time at each vertex
  Vec3 center_{};
  double radiusMm_ = 0.0;
  double lengthMm_ = 0.0;
  double feedMmMin_ = 0.0;
};

}  // namespace volcomp::sim
