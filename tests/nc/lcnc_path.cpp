#include "lcnc_path.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace volcomp::testing {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<double> numbersIn(const std::string& args) {
  std::vector<double> out;
  std::size_t i = 0;
  while (i < args.size()) {
    while (i < args.size() && (args[i] == ' ' || args[i] == ',')) ++i;
    std::size_t j = i;
    while (j < args.size() && args[j] != ' ' && args[j] != ',') ++j;
    if (j > i) {
      double v = 0.0;
      const auto [end, ec] = std::from_chars(args.data() + i, args.data() + j, v);
      if (ec == std::errc() && end == args.data() + j) out.push_back(v);
    }
    i = j;
  }
  return out;
}

struct Segment {
  Vec3 a, b;
  model::Directions dirs{};
  bool rapid = false;
  long n = -1;     // N word of the original move
  long move = -1;  // index of the original feed move it belongs to
};

double pointSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Nearest segment to a point, with the segments in a uniform grid of cells at least as large as
// the longest segment: a segment closer than one cell to the point is registered in one of the
// 27 cells around it; farther ones are found by a full scan.
class Nearest {
 public:
  explicit Nearest(const std::vector<Segment>& segments) : s_(segments) {
    for (const Segment& seg : s_) cell_ = std::max(cell_, (seg.b - seg.a).norm());
    for (std::uint32_t i = 0; i < s_.size(); ++i) {
      const Vec3 lo = s_[i].a.cwiseMin(s_[i].b), hi = s_[i].a.cwiseMax(s_[i].b);
      const auto a = key(lo), b = key(hi);
      for (long x = a[0]; x <= b[0]; ++x) {
        for (long y = a[1]; y <= b[1]; ++y) {
          for (long z = a[2]; z <= b[2]; ++z) grid_[pack(x, y, z)].push_back(i);
        }
      }
    }
  }
  std::size_t find(const Vec3& p, double* distance) const {
    std::size_t best = s_.size();
    double bestD = 1e300;
    const auto c = key(p);
    for (long x = c[0] - 1; x <= c[0] + 1; ++x) {
      for (long y = c[1] - 1; y <= c[1] + 1; ++y) {
        for (long z = c[2] - 1; z <= c[2] + 1; ++z) {
          const auto it = grid_.find(pack(x, y, z));
          if (it == grid_.end()) continue;
          for (std::uint32_t i : it->second) {
            const double d = pointSegment(p, s_[i].a, s_[i].b);
            if (d < bestD || (d == bestD && i < best)) {
              bestD = d;
              best = i;
            }
          }
        }
      }
    }
    if (bestD > cell_) {
      for (std::size_t i = 0; i < s_.size(); ++i) {
        const double d = pointSegment(p, s_[i].a, s_[i].b);
        if (d < bestD) {
          bestD = d;
          best = i;
        }
      }
    }
    *distance = bestD;
    return best;
  }

 private:
  std::array<long, 3> key(const Vec3& p) const {
    return {static_cast<long>(std::floor(p.x() / cell_)),
            static_cast<long>(std::floor(p.y() / cell_)),
            static_cast<long>(std::floor(p.z() / cell_))};
  }
  static std::uint64_t pack(long x, long y, long z) {
    const auto u = [](long v) { return static_cast<std::uint64_t>(v + (1l << 20)) & 0x1fffff; };
    return (u(x) << 42) | (u(y) << 21) | u(z);
  }
  const std::vector<Segment>& s_;
  double cell_ = 0.5;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;
};

model::Directions step(model::Directions d, const Vec3& a, const Vec3& b) {
  for (int k = 0; k < 3; ++k) {
    if (b[k] > a[k]) d[static_cast<std::size_t>(k)] = model::Direction::Positive;
    if (b[k] < a[k]) d[static_cast<std::size_t>(k)] = model::Direction::Negative;
  }
  return d;
}

// Directions of travel on the original path for a compensated piece: on the original move with
// the piece's N word when there is one (a piece near a vertex may be nearer to the next move),
// else on the original move the piece belongs to in the order of the program (`move`, see
// checkCompensation), else on the nearest original segment.
model::Directions directionsFor(const std::vector<Segment>& feed, const Nearest& nearest, long n,
                                long move, const Vec3& p) {
  const auto nearestWhere = [&](auto&& belongs) -> const Segment* {
    double best = 1e300;
    const Segment* found = nullptr;
    for (const Segment& s : feed) {
      if (!belongs(s)) continue;
      const double d = pointSegment(p, s.a, s.b);
      if (d < best) {
        best = d;
        found = &s;
      }
    }
    return found;
  };
  if (n >= 0) {
    if (const Segment* s = nearestWhere([n](const Segment& x) { return x.n == n; })) return s->dirs;
  }
  if (move >= 0) {
    if (const Segment* s = nearestWhere([move](const Segment& x) { return x.move == move; }))
      return s->dirs;
  }
  double ignored = 0.0;
  return feed[nearest.find(p, &ignored)].dirs;
}

}  // namespace

double PathCheck::worst() const {
  return std::max({tipToOriginalMm, originalToTipMm, rapidEndsMm});
}

std::vector<CanonMotion> parseCanonical(const std::string& text, const Vec3& start) {
  std::vector<CanonMotion> motions;
  double unit = 1.0;
  int plane = 0;
  Vec3 g5x = Vec3::Zero(), g92 = Vec3::Zero(), tool = Vec3::Zero();
  Vec3 position = start;
  bool mark = false;
  long lastN = -1;
  std::istringstream lines(text);
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::size_t n = line.find('N');
    const std::size_t open = line.find('(');
    if (n == std::string::npos || open == std::string::npos || open < n) {
      throw std::runtime_error("canonical line " + std::to_string(number) + ": " + line);
    }
    long nWord = -1;
    if (n + 1 < open && std::isdigit(static_cast<unsigned char>(line[n + 1]))) {
      nWord = std::stol(line.substr(n + 1));
    }
    std::size_t nameStart = n + 1;
    while (nameStart < open && (std::isdigit(static_cast<unsigned char>(line[nameStart])) ||
                                line[nameStart] == '.' || line[nameStart] == ' ')) {
      ++nameStart;
    }
    const std::string name = line.substr(nameStart, open - nameStart);
    const std::string args = line.substr(open + 1, line.rfind(')') - open - 1);
    const std::vector<double> v = numbersIn(args);
    if (name == "USE_LENGTH_UNITS") {
      unit = args.find("INCHES") != std::string::npos ? 25.4 : 1.0;
    } else if (name == "SET_G5X_OFFSET") {
      g5x = Vec3(v.at(1), v.at(2), v.at(3)) * unit;
    } else if (name == "SET_G92_OFFSET") {
      g92 = Vec3(v.at(0), v.at(1), v.at(2)) * unit;
    } else if (name == "USE_TOOL_LENGTH_OFFSET") {
      tool = Vec3(v.at(0), v.at(1), v.at(2)) * unit;
    } else if (name == "SELECT_PLANE") {
      plane = args.find("XZ") != std::string::npos   ? 1
              : args.find("YZ") != std::string::npos ? 2
                                                     : 0;
    } else if (name == "COMMENT") {
      mark = args.find("volcomp:") != std::string::npos;
    } else if (name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED" || name == "ARC_FEED") {
      CanonMotion m;
      m.line = number;
      if (nWord >= 0) lastN = nWord;
      m.n = lastN;
      m.start = position;
      m.marked = mark;
      mark = false;
      const Vec3 shift = g5x + g92 + tool;
      if (name == "ARC_FEED") {
        static constexpr int kAxes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};
        m.kind = CanonMotion::Arc;
        m.first = kAxes[plane][0];
        m.second = kAxes[plane][1];
        m.normal = kAxes[plane][2];
        m.end[m.first] = v.at(0) * unit + shift[m.first];
        m.end[m.second] = v.at(1) * unit + shift[m.second];
        m.centerFirst = v.at(2) * unit + shift[m.first];
        m.centerSecond = v.at(3) * unit + shift[m.second];
        m.rotation = static_cast<int>(v.at(4));
        m.end[m.normal] = v.at(5) * unit + shift[m.normal];
      } else {
        m.kind = name == "STRAIGHT_TRAVERSE" ? CanonMotion::Rapid : CanonMotion::Feed;
        m.end = Vec3(v.at(0), v.at(1), v.at(2)) * unit + shift;
      }
      position = m.end;
      motions.push_back(m);
    }
  }
  return motions;
}

std::vector<Vec3> samplePoints(const CanonMotion& m, double stepMm) {
  std::vector<Vec3> pts;
  if (m.kind != CanonMotion::Arc) {
    const int n = std::max(1, static_cast<int>(std::ceil((m.end - m.start).norm() / stepMm)));
    for (int i = 0; i <= n; ++i)
      pts.push_back(m.start + (static_cast<double>(i) / n) * (m.end - m.start));
    pts.back() = m.end;
    return pts;
  }
  // LinuxCNC's arc: from the start around the centre to the end in the direction of the
  // rotation, |rotation| - 1 extra turns, the radius changing linearly with the angle.
  const double s1 = m.start[m.first] - m.centerFirst, s2 = m.start[m.second] - m.centerSecond;
  const double e1 = m.end[m.first] - m.centerFirst, e2 = m.end[m.second] - m.centerSecond;
  const double r0 = std::hypot(s1, s2), r1 = std::hypot(e1, e2);
  const double a0 = std::atan2(s2, s1);
  double sweep = std::atan2(e2, e1) - a0;
  const bool full = std::hypot(e1 - s1, e2 - s2) <= 1e-9 * std::max(1.0, r0);
  const int turns = std::abs(m.rotation);
  if (m.rotation > 0) {
    while (sweep <= 0.0) sweep += 2 * kPi;
    if (full) sweep = 2 * kPi;
    sweep += 2 * kPi * (turns - 1);
  } else {
    while (sweep >= 0.0) sweep -= 2 * kPi;
    if (full) sweep = -2 * kPi;
    sweep -= 2 * kPi * (turns - 1);
  }
  const double radius = std::max(r0, r1);
  // Chord error r (1 - cos(d/2)) <= 1e-6 mm, and at most stepMm apart.
  double maxAngle = stepMm / std::max(radius, 1e-9);
  if (radius > 1e-6) maxAngle = std::min(maxAngle, 2.0 * std::acos(1.0 - 1e-6 / radius));
  const double length = std::hypot(std::abs(sweep) * radius, m.end[m.normal] - m.start[m.normal]);
  const int n = std::max({1, static_cast<int>(std::ceil(std::abs(sweep) / maxAngle)),
                          static_cast<int>(std::ceil(length / stepMm))});
  for (int i = 0; i <= n; ++i) {
    const double u = static_cast<double>(i) / n;
    const double angle = a0 + u * sweep;
    const double r = r0 + u * (r1 - r0);
    Vec3 p;
    p[m.first] = m.centerFirst + r * std::cos(angle);
    p[m.second] = m.centerSecond + r * std::sin(angle);
    p[m.normal] = m.start[m.normal] + u * (m.end[m.normal] - m.start[m.normal]);
    pts.push_back(p);
  }
  pts.front() = m.start;
  pts.back() = m.end;
  return pts;
}

PathCheck checkCompensation(const model::MachineModel& model,
                            const std::vector<CanonMotion>& original,
                            const std::vector<CanonMotion>& compensated, double stepMm) {
  PathCheck result;
  model::Workspace ws;
  const auto tip = [&](const Vec3& q, const model::Directions& d) {
    return Vec3(q + model::evaluate(model, ws, q, d).errorMm);
  };
  // The original path as fine segments with the direction of travel of each axis on them.
  std::vector<Segment> feed;
  std::vector<std::pair<Vec3, model::Directions>> rapidEnds;
  std::vector<const CanonMotion*> feedMoves;  // the original's feed moves in program order
  std::vector<double> feedLengths;            // and their lengths (mm)
  model::Directions dirs{};
  for (const CanonMotion& m : original) {
    const std::vector<Vec3> pts = samplePoints(m, 0.5);
    const long move = static_cast<long>(feedMoves.size());
    for (std::size_t i = 1; i < pts.size(); ++i) {
      dirs = step(dirs, pts[i - 1], pts[i]);
      if (m.kind != CanonMotion::Rapid)
        feed.push_back(Segment{pts[i - 1], pts[i], dirs, false, m.n, move});
    }
    if (m.kind == CanonMotion::Rapid) rapidEnds.emplace_back(m.end, dirs);
    if (m.kind != CanonMotion::Rapid && pts.size() > 1) {
      double length = 0.0;
      for (std::size_t i = 1; i < pts.size(); ++i) length += (pts[i] - pts[i - 1]).norm();
      if (length > 0.0) {
        feedMoves.push_back(&m);
        feedLengths.push_back(length);
      }
    }
  }
  const Nearest nearestOriginal(feed);
  // The tool tip along the compensated program.
  std::vector<Segment> tipPath;
  std::size_t rapid = 0;
  std::size_t current = 0;  // the original feed move the next compensated piece belongs to
  double consumedMm = 0.0;  // length of the compensated pieces given to it so far
  model::Directions lastDirections{};
  bool connected = false;
  Vec3 previous = Vec3::Zero();  // the last tool-tip sample (the tip path goes on from it)
  for (const CanonMotion& m : compensated) {
    if (m.kind == CanonMotion::Rapid) {
      connected = false;
      // A rapid that does not move (rs274 prints one for a bare G0) leaves the tool where it was.
      if (rapid < rapidEnds.size() && m.end != m.start) {
        const auto& [end, d] = rapidEnds[rapid];
        lastDirections = d;
        const double e = (tip(m.end, d) - end).norm();
        if (e > result.rapidEndsMm) {
          if (e > result.worst())
            result.worstAt = "rapid ending at canonical line " + std::to_string(m.line);
          result.rapidEndsMm = e;
        }
      }
      ++rapid;
      ++result.rapids;
      continue;
    }
    if (m.marked) {
      ++result.markedMoves;
      continue;
    }
    if (feed.empty()) continue;
    const std::vector<Vec3> pts = samplePoints(m, stepMm);
    // The compensated pieces follow the original moves in order: a piece belongs to the current
    // original move, and the piece whose tool tip ends at that move's end closes it. Where the
    // moves are as short as the offsets (tens of micrometres) the nearest segment may be a
    // neighbour's, with the other direction of travel.
    const long move = current < feedMoves.size() ? static_cast<long>(current) : -1;
    // A move of no length (a programmed move to where the tool is) is a point of the previous
    // move and keeps its directions.
    const bool still = (m.end - m.start).norm() == 0.0 && m.kind != CanonMotion::Arc;
    const model::Directions d =
        still ? lastDirections
              : directionsFor(feed, nearestOriginal, m.n, move, pts[pts.size() / 2]);
    lastDirections = d;
    if (move >= 0) {
      // A piece closes the move when its tip ends at the move's end after about the move's
      // length (a multi-turn arc passes its end point on every turn).
      for (std::size_t i = 1; i < pts.size(); ++i) consumedMm += (pts[i] - pts[i - 1]).norm();
      const CanonMotion& o = *feedMoves[current];
      const double closeMm = std::min(0.01, 0.3 * feedLengths[current]);
      if ((tip(m.end, d) - o.end).norm() <= closeMm &&
          consumedMm >= 0.9 * feedLengths[current] - 0.02) {
        ++current;
        consumedMm = 0.0;
      }
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec3 t = tip(pts[i], d);
      double distance = 0.0;
      nearestOriginal.find(t, &distance);
      if (distance > result.tipToOriginalMm) {
        if (distance > result.worst()) {
          std::ostringstream where;
          where << "tool tip " << t.transpose() << " of the compensated move at canonical line "
                << m.line << " (machine " << pts[i].transpose() << ")";
          result.worstAt = where.str();
        }
        result.tipToOriginalMm = distance;
      }
      ++result.tipSamples;
      if (i > 0 || connected) tipPath.push_back(Segment{previous, t, d, false});
      previous = t;
    }
    connected = true;
  }
  // Every original point must be reached by the tool tip.
  if (tipPath.empty()) return result;
  const Nearest nearestTip(tipPath);
  for (const CanonMotion& m : original) {
    if (m.kind == CanonMotion::Rapid) continue;
    // Every 5 steps: the tip path it is compared with is sampled every step.
    for (const Vec3& p : samplePoints(m, 5.0 * stepMm)) {
      double distance = 0.0;
      nearestTip.find(p, &distance);
      ++result.originalSamples;
      if (distance > result.originalToTipMm) {
        if (distance > result.worst()) {
          std::ostringstream where;
          where << "original point " << p.transpose() << " (canonical line " << m.line
                << ") not reached by the tool tip";
          result.worstAt = where.str();
        }
        result.originalToTipMm = distance;
      }
    }
  }
  return result;
}

}  // namespace volcomp::testing
