#include "volcomp/sim/path.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "volcomp/config/csv_table.hpp"

namespace volcomp::sim {
namespace {

double distance(const Vec3& a, const Vec3& b) noexcept {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

void checkFeed(double feedMmMin) {
  if (!(feedMmMin > 0.0) || !std::isfinite(feedMmMin)) {
    throw std::invalid_argument("path feed must be a positive number of mm/min");
  }
}

// Exact-stop timing of one segment of length lengthMm: duration, and the distance covered after
// tS of it (trapezoid, or triangle when the feed is not reached).
struct SegmentProfile {
  double lengthMm, feedMmS, accelMmS2;
  double rampS() const noexcept {
    return std::min(feedMmS / accelMmS2, std::sqrt(lengthMm / accelMmS2));
  }
  double durationS() const noexcept {
    const double ramp = rampS();
    const double rampMm = accelMmS2 * ramp * ramp;  // both ramps
    return 2.0 * ramp + (lengthMm - rampMm) / feedMmS;
  }
  double distanceMm(double tS) const noexcept {
    const double ramp = rampS(), total = durationS();
    if (tS <= ramp) return 0.5 * accelMmS2 * tS * tS;
    if (tS >= total - ramp) {
      const double left = std::max(0.0, total - tS);
      return lengthMm - 0.5 * accelMmS2 * left * left;
    }
    return 0.5 * accelMmS2 * ramp * ramp + accelMmS2 * ramp * (tS - ramp);
  }
};

}  // namespace

Path Path::withAcceleration(double accelMmS2) const {
  if (kind_ != Kind::Polyline)
    throw std::invalid_argument("only a polyline path has corners to brake at");
  if (!(accelMmS2 > 0.0) || !std::isfinite(accelMmS2)) {
    throw std::invalid_argument("path acceleration must be a positive number of mm/s^2");
  }
  Path p = *this;
  p.accelMmS2_ = accelMmS2;
  p.cumS_.assign(1, 0.0);
  for (std::size_t i = 1; i < points_.size(); ++i) {
    const SegmentProfile seg{cumMm_[i] - cumMm_[i - 1], feedMmMin_ / 60.0, accelMmS2};
    p.cumS_.push_back(p.cumS_.back() + seg.durationS());
  }
  return p;
}

Path Path::polyline(std::vector<Vec3> points, double feedMmMin) {
  checkFeed(feedMmMin);
  if (points.empty()) throw std::invalid_argument("a path needs at least one point");
  Path p;
  p.kind_ = Kind::Polyline;
  p.feedMmMin_ = feedMmMin;
  points.push_back(points.front());
  p.cumMm_.reserve(points.size());
  double s = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i > 0) s += distance(points[i - 1], points[i]);
    p.cumMm_.push_back(s);
  }
  p.points_ = std::move(points);
  p.lengthMm_ = s;
  return p;
}

Path Path::raster(const Vec3& from, const Vec3& to, double stepMm, double feedMmMin) {
  if (!(stepMm > 0.0)) throw std::invalid_argument("raster step must be positive");
  auto levels = [stepMm](double a, double b) {
    std::vector<double> v;
    const double dir = b >= a ? 1.0 : -1.0;
    const auto n = static_cast<int>(std::floor(std::abs(b - a) / stepMm + 1e-9));
    for (int i = 0; i <= n; ++i) v.push_back(a + dir * stepMm * i);
    if (std::abs(v.back() - b) > 1e-9) v.push_back(b);
    return v;
  };
  std::vector<Vec3> pts;
  bool forward = true;
  for (double z : levels(from[2], to[2])) {
    for (double y : levels(from[1], to[1])) {
      const double x0 = forward ? from[0] : to[0];
      const double x1 = forward ? to[0] : from[0];
      pts.push_back({x0, y, z});
      pts.push_back({x1, y, z});
      forward = !forward;
    }
  }
  return polyline(std::move(pts), feedMmMin);
}

Path Path::circle(const Vec3& center, double radiusMm, double feedMmMin) {
  checkFeed(feedMmMin);
  if (!(radiusMm > 0.0)) throw std::invalid_argument("circle radius must be positive");
  Path p;
  p.kind_ = Kind::Circle;
  p.center_ = center;
  p.radiusMm_ = radiusMm;
  p.lengthMm_ = 2.0 * std::numbers::pi * radiusMm;
  p.feedMmMin_ = feedMmMin;
  return p;
}

Path Path::fromCsv(const std::string& file, double feedMmMin) {
  // The one CSV reader of volcomp: header with x,y,z in any order (unit suffixes allowed),
  // comments; columns of eval's or the calibration's files are accepted and not read.
  config::CsvSchema schema;
  schema.add({"x", "y", "z"}, config::CsvQuantity::Length, true)
      .ignore({"tx", "ty", "tz", "direction", "ex", "ey", "ez", "ea", "eb", "ec", "ox", "oy", "oz",
               "weight"});
  std::ifstream in = config::CsvReader::open(file);
  config::CsvReader csv(in, file, std::move(schema));
  const int x = csv.column("x"), y = csv.column("y"), z = csv.column("z");
  std::vector<Vec3> pts;
  while (csv.next()) pts.push_back(Vec3{csv.number(x), csv.number(y), csv.number(z)});
  if (pts.empty()) throw config::ConfigError(file, "", "no points");
  return polyline(std::move(pts), feedMmMin);
}

Vec3 Path::at(double pathTimeS) const noexcept {
  if (lengthMm_ <= 0.0) return kind_ == Kind::Circle ? center_ : points_.front();
  if (accelMmS2_ > 0.0) {
    const double t = std::fmod(std::max(0.0, pathTimeS), cumS_.back());
    const auto it = std::upper_bound(cumS_.begin(), cumS_.end(), t);
    const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - cumS_.begin()));
    if (i >= points_.size()) return points_.back();
    const SegmentProfile seg{cumMm_[i] - cumMm_[i - 1], feedMmMin_ / 60.0, accelMmS2_};
    const double f = seg.lengthMm > 0.0 ? seg.distanceMm(t - cumS_[i - 1]) / seg.lengthMm : 0.0;
    Vec3 out{};
    for (std::size_t k = 0; k < 3; ++k)
      out[k] = points_[i - 1][k] + f * (points_[i][k] - points_[i - 1][k]);
    return out;
  }
  double s = std::fmod(feedMmMin_ / 60.0 * std::max(0.0, pathTimeS), lengthMm_);
  if (kind_ == Kind::Circle) {
    const double a = s / radiusMm_;
    return {center_[0] + radiusMm_ * std::cos(a), center_[1] + radiusMm_ * std::sin(a), center_[2]};
  }
  const auto it = std::upper_bound(cumMm_.begin(), cumMm_.end(), s);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - cumMm_.begin()));
  if (i >= points_.size()) return points_.back();
  const double seg = cumMm_[i] - cumMm_[i - 1];
  const double f = seg > 0.0 ? (s - cumMm_[i - 1]) / seg : 0.0;
  Vec3 out{};
  for (std::size_t k = 0; k < 3; ++k)
    out[k] = points_[i - 1][k] + f * (points_[i][k] - points_[i - 1][k]);
  return out;
}

std::array<Vec3, 2> Path::bounds() const noexcept {
  if (kind_ == Kind::Circle) {
    return {Vec3{center_[0] - radiusMm_, center_[1] - radiusMm_, center_[2]},
            Vec3{center_[0] + radiusMm_, center_[1] + radiusMm_, center_[2]}};
  }
  Vec3 lo = points_.front(), hi = points_.front();
  for (const auto& p : points_) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  return {lo, hi};
}

}  // namespace volcomp::sim
