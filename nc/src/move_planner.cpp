#include "move_planner.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "volcomp/nc/nc_error.hpp"

namespace volcomp::nc::detail {
namespace {

using model::Direction;
using model::Directions;

constexpr double kPi = std::numbers::pi;

Direction sign(double v) {
  return v > 0.0 ? Direction::Positive : v < 0.0 ? Direction::Negative : Direction::Unknown;
}

std::uint32_t addSolve(ChunkPlan& plan, const Vec3& q, const Directions& d, long line) {
  plan.solveQ.push_back(q);
  plan.solveDirs.push_back(d);
  plan.solveLine.push_back(line);
  return static_cast<std::uint32_t>(plan.solveQ.size() - 1);
}

void addSample(ChunkPlan& plan, double u, std::uint32_t ref) {
  plan.sampleU.push_back(u);
  plan.sampleRef.push_back(ref);
}

}  // namespace

MovePlanner::MovePlanner(const OffsetField& field, double toleranceMm, double checkStepMm,
                         std::size_t maxCheckPointsPerMove, const std::string& file)
    : field_(field),
      tolerance_(toleranceMm),
      checkStep_(checkStepMm),
      maxCheckPoints_(maxCheckPointsPerMove),
      file_(file),
      bidirectional_(field.bidirectionalAxes()) {}

Directions MovePlanner::masked(Directions d) const {
  for (int k = 0; k < 3; ++k) {
    if ((bidirectional_ & (1u << k)) == 0) d[static_cast<std::size_t>(k)] = Direction::Unknown;
  }
  return d;
}

Directions MovePlanner::lineDirections(const Move& m) const {
  Directions d = lastDirs_;
  for (int k = 0; k < 3; ++k) {
    const Direction s = sign(m.endMm[k] - m.startMm[k]);
    if (s != Direction::Unknown) d[static_cast<std::size_t>(k)] = s;
  }
  return masked(d);
}

// Directions of travel along an arc at parameter u (derivative of the
// position), keeping the last direction for axes that do not move.
Directions MovePlanner::arcDirections(const Move& m, double u, const Directions& previous) const {
  const ArcGeometry& a = m.arc;
  const double angle = a.startAngle + u * a.sweep;
  const double radius = a.startRadius + u * (a.endRadius - a.startRadius);
  const double dr = a.endRadius - a.startRadius;
  Vec3 velocity;
  velocity[a.first] = dr * std::cos(angle) - radius * std::sin(angle) * a.sweep;
  velocity[a.second] = dr * std::sin(angle) + radius * std::cos(angle) * a.sweep;
  velocity[a.normal] = a.endNormal - a.startNormal;
  Directions d = previous;
  for (int k = 0; k < 3; ++k) {
    const Direction s = sign(velocity[k]);
    if (s != Direction::Unknown) d[static_cast<std::size_t>(k)] = s;
  }
  return masked(d);
}

void MovePlanner::addLineKinks(const Move& m) {
  for (int k = 0; k < 3; ++k) {
    const double a = m.startMm[k];
    const double delta = m.endMm[k] - a;
    if (delta == 0.0) continue;
    const std::vector<double>& kinks = field_.kinks(k);
    const double lo = std::min(a, a + delta);
    const double hi = std::max(a, a + delta);
    for (auto it = std::upper_bound(kinks.begin(), kinks.end(), lo); it != kinks.end() && *it < hi;
         ++it) {
      boundaries_.push_back((*it - a) / delta);
    }
  }
}

// Angles (as u) in the open sweep where the arc's coordinate along `axis`
// equals value, for base solutions phi of the circle (the mean radius; a spiral
// moves them by its radius change).
void MovePlanner::addAngles(const ArcGeometry& a, double phi) {
  const double lo = std::min(a.startAngle, a.startAngle + a.sweep);
  const double hi = std::max(a.startAngle, a.startAngle + a.sweep);
  const double twoPi = 2.0 * kPi;
  for (double n = std::ceil((lo - phi) / twoPi); phi + n * twoPi < hi; n += 1.0) {
    const double theta = phi + n * twoPi;
    if (theta > lo) boundaries_.push_back((theta - a.startAngle) / a.sweep);
  }
}

void MovePlanner::addArcKinks(const Move& m) {
  const ArcGeometry& a = m.arc;
  const double radius = 0.5 * (a.startRadius + a.endRadius);
  if (radius <= 0.0 || a.sweep == 0.0) return;
  for (int which = 0; which < 2; ++which) {
    const int axis = which == 0 ? a.first : a.second;
    const double centre = which == 0 ? a.centerFirst : a.centerSecond;
    const std::vector<double>& kinks = field_.kinks(axis);
    for (auto it = std::upper_bound(kinks.begin(), kinks.end(), centre - radius);
         it != kinks.end() && *it < centre + radius; ++it) {
      const double v = std::clamp((*it - centre) / radius, -1.0, 1.0);
      if (which == 0) {
        addAngles(a, std::acos(v));
        addAngles(a, -std::acos(v));
      } else {
        addAngles(a, std::asin(v));
        addAngles(a, kPi - std::asin(v));
      }
    }
    // Where the axis turns round (a bidirectional axis changes its direction
    // there).
    if ((bidirectional_ & (1u << axis)) != 0) {
      addAngles(a, which == 0 ? 0.0 : kPi / 2);
      addAngles(a, which == 0 ? kPi : -kPi / 2);
    }
  }
  const double delta = a.endNormal - a.startNormal;
  if (delta != 0.0) {
    const std::vector<double>& kinks = field_.kinks(a.normal);
    const double lo = std::min(a.startNormal, a.endNormal);
    const double hi = std::max(a.startNormal, a.endNormal);
    for (auto it = std::upper_bound(kinks.begin(), kinks.end(), lo); it != kinks.end() && *it < hi;
         ++it) {
      boundaries_.push_back((*it - a.startNormal) / delta);
    }
  }
}

// Boundaries closer than 1e-9, or than a tenth of the tolerance along the move,
// to the previous one (or to the end) are dropped. An arc whose end is an axis'
// extremum, written with a few decimals, passes it by a few tens of nanometres
// of path, in which the axis moves back by picometres: that is no reversal (a
// machine does not turn its direction for that), and a section there would
// write two and compensate the next move, if that axis stands still in it, with
// the wrong direction.
void MovePlanner::dropCloseBoundaries(const Move& m) {
  const double gap = std::max(1e-9, 0.1 * tolerance_ / std::max(m.lengthMm(), 1e-12));
  std::size_t kept = 1;
  for (std::size_t i = 1; i + 1 < boundaries_.size(); ++i) {
    if (boundaries_[i] > boundaries_[kept - 1] + gap && boundaries_[i] < 1.0 - gap) {
      boundaries_[kept++] = boundaries_[i];
    }
  }
  boundaries_[kept++] = 1.0;
  boundaries_.resize(kept);
}

// A work offset of 1e308 mm puts a move beyond kMaxPositionMm in the frame its
// coordinates are written in even where its machine position is fine.
void MovePlanner::refuseOutOfRange(const MotionWork& w) const {
  static constexpr char kAxes[3] = {'X', 'Y', 'Z'};
  const auto check = [&](const Vec3& machineMm, const PrintMode& mode) {
    const Vec3 shift = mode.machineCoordinates ? Vec3::Zero() : mode.frame.shiftMm;
    for (int k = 0; k < 3; ++k) {
      const double programMm = machineMm[k] - shift[k];
      if (std::abs(machineMm[k]) <= kMaxPositionMm && std::abs(programMm) <= kMaxPositionMm) {
        continue;  // also refuses NaN
      }
      std::ostringstream message;
      message << kAxes[k] << " at " << machineMm[k] << " mm in machine coordinates (" << programMm
              << " mm in the program's frame) is beyond +-" << kMaxPositionMm
              << " mm: is a work offset or the unit wrong?";
      throw NcError(file_, w.line, 0, message.str());
    }
  };
  check(w.move.endMm, w.after);
  if (w.startKnown) check(w.move.startMm, w.before);
}

void MovePlanner::refuseOversized(const MotionWork& w) const {
  const Move& m = w.move;
  double needed = m.lengthMm() / checkStep_;
  if (m.kind == MoveKind::Arc) {
    const double radius = std::max(m.arc.startRadius, m.arc.endRadius);
    if (radius > 0.5 * tolerance_) {
      needed += 2.0 * std::abs(m.arc.sweep) / (2.0 * std::acos(1.0 - 0.5 * tolerance_ / radius));
    }
  }
  const double most = static_cast<double>(maxCheckPoints_);
  if (needed <= most) return;  // also refuses NaN
  std::ostringstream message;
  message << "a move of " << m.lengthMm() << " mm needs about " << needed
          << " check points at the check step of " << checkStep_ << " mm, more than the "
          << maxCheckPoints_ << " one move may have (is the program in the machine's units?)";
  throw NcError(file_, w.line, 0, message.str());
}

void MovePlanner::startChunk(ChunkPlan& plan) {
  plan.solveQ.clear();
  plan.solveDirs.clear();
  plan.solveLine.clear();
  plan.sampleU.clear();
  plan.sampleRef.clear();
  plan.sections.clear();
  plan.planned.clear();
  prevEndRef_ = -1;
}

void MovePlanner::plan(const MotionWork& w, ChunkPlan& plan) {
  Planned p;
  p.sampleBegin = static_cast<std::uint32_t>(plan.sampleU.size());
  p.sectionBegin = static_cast<std::uint32_t>(plan.sections.size());
  const Move& m = w.move;
  if (!w.endKnown) {
    // Copied unchanged: where the machine is afterwards is not known to us.
    prevEndRef_ = -1;
    p.sampleEnd = p.sampleBegin;
    p.sectionEnd = p.sectionBegin;
    plan.planned.push_back(p);
    return;
  }
  refuseOutOfRange(w);
  if (m.kind == MoveKind::Rapid || !w.startKnown) {
    Directions d = w.startKnown ? lineDirections(m) : masked(lastDirs_);
    const std::uint32_t ref = addSolve(plan, m.endMm, d, w.line);
    addSample(plan, 1.0, ref);
    lastDirs_ = d;
    prevEndRef_ = ref;
    prevEndDirs_ = d;
    p.sampleEnd = static_cast<std::uint32_t>(plan.sampleU.size());
    p.sectionEnd = p.sectionBegin;
    plan.planned.push_back(p);
    return;
  }
  p.split = true;
  refuseOversized(w);
  planSections(w, plan, p);
  p.sampleEnd = static_cast<std::uint32_t>(plan.sampleU.size());
  p.sectionEnd = static_cast<std::uint32_t>(plan.sections.size());
  plan.planned.push_back(p);
}

void MovePlanner::planSections(const MotionWork& w, ChunkPlan& plan, Planned& p) {
  const Move& m = w.move;
  boundaries_.clear();
  boundaries_.push_back(0.0);
  if (m.kind == MoveKind::Line) {
    addLineKinks(m);
  } else {
    addArcKinks(m);
  }
  boundaries_.push_back(1.0);
  std::sort(boundaries_.begin(), boundaries_.end());
  dropCloseBoundaries(m);
  const double length = m.lengthMm();
  Directions dirs = m.kind == MoveKind::Line ? lineDirections(m) : lastDirs_;
  const Directions startDirs =
      m.kind == MoveKind::Line ? dirs : arcDirections(m, 0.5 * boundaries_[1], lastDirs_);
  // Start sample: the previous move's end when the directions agree.
  if (prevEndRef_ >= 0 && prevEndDirs_ == startDirs) {
    addSample(plan, 0.0, static_cast<std::uint32_t>(prevEndRef_));
  } else {
    addSample(plan, 0.0, addSolve(plan, m.startMm, startDirs, w.line));
  }
  dirs = startDirs;
  for (std::size_t b = 0; b + 1 < boundaries_.size(); ++b) {
    const double u0 = boundaries_[b];
    const double u1 = boundaries_[b + 1];
    Directions d = m.kind == MoveKind::Line ? dirs : arcDirections(m, 0.5 * (u0 + u1), dirs);
    const bool hard = d != dirs;
    if (hard) {
      // The left end keeps the old directions (already sampled); the right side
      // starts anew.
      addSample(plan, u0, addSolve(plan, m.at(u0), d, w.line));
    }
    dirs = d;
    // Arcs: pieces short enough for the circle's own sagitta (half the
    // tolerance).
    int arcPieces = 1;
    if (m.kind == MoveKind::Arc) {
      const double radius = std::max(m.arc.startRadius, m.arc.endRadius);
      const double sweep = std::abs(m.arc.sweep) * (u1 - u0);
      if (radius > 0.5 * tolerance_) {
        const double maxAngle = 2.0 * std::acos(1.0 - 0.5 * tolerance_ / radius);
        arcPieces = std::max(1, static_cast<int>(std::ceil(sweep / maxAngle)));
      }
    }
    for (int piece = 0; piece < arcPieces; ++piece) {
      const double a = u0 + (u1 - u0) * piece / arcPieces;
      const double e = piece + 1 == arcPieces ? u1 : u0 + (u1 - u0) * (piece + 1) / arcPieces;
      Section s;
      s.first = static_cast<std::uint32_t>(plan.sampleU.size() - 1 - p.sampleBegin);
      s.dirs = d;
      s.hardStart = hard && piece == 0;
      const int intervals = std::max(2, static_cast<int>(std::ceil(length * (e - a) / checkStep_)));
      for (int j = 1; j < intervals; ++j) {
        const double u = a + (e - a) * j / intervals;
        addSample(plan, u, addSolve(plan, m.at(u), d, w.line));
      }
      addSample(plan, e, addSolve(plan, m.at(e), d, w.line));
      s.last = static_cast<std::uint32_t>(plan.sampleU.size() - 1 - p.sampleBegin);
      plan.sections.push_back(s);
    }
  }
  lastDirs_ = dirs;
  prevEndRef_ = plan.sampleRef.back();
  prevEndDirs_ = dirs;
}

}  // namespace volcomp::nc::detail
