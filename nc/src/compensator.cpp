#include "volcomp/nc/compensator.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "volcomp/nc/move.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc {
namespace {

using model::Direction;
using model::Directions;
using Clock = std::chrono::steady_clock;

constexpr double kPi = std::numbers::pi;
constexpr int kMaxRefineDepth = 12;
constexpr double kMinPieceMm = 1e-7;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

Direction sign(double v) {
  return v > 0.0 ? Direction::Positive : v < 0.0 ? Direction::Negative : Direction::Unknown;
}

// A section of a move between two boundaries (kinks, quadrant points of arcs, pieces of an arc):
// its samples are [first, last] in the motion's sample list, uniformly spaced in u.
struct Section {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
  Directions dirs{};
  bool hardStart = false;  // directions change here: always a vertex, maybe a reversal
};

struct Planned {
  std::uint32_t sampleBegin = 0;
  std::uint32_t sampleEnd = 0;
  std::uint32_t sectionBegin = 0;
  std::uint32_t sectionEnd = 0;
  bool split = false;  // a feed move planned in sections (else only its end point)
};

struct Printed {
  Vec3 machineMm = Vec3::Zero();
  std::array<std::int64_t, 3> counts{};
};

enum class PieceKind : std::uint8_t { Normal, Reversal, LeadIn };

struct Piece {
  std::array<std::int64_t, 3> counts{};
  PieceKind kind = PieceKind::Normal;
  const PrintMode* mode = nullptr;
};

}  // namespace

Decimals decimalsForTolerance(double toleranceMm) noexcept {
  // Rounding each coordinate by half a unit of the last decimal moves a point by at most
  // 0.5 * 10^-d * sqrt(3) units.
  const auto needed = [&](double unitMm, int minimum) {
    int d = minimum;
    while (d < 9 && 0.5 * std::pow(10.0, -d) * std::sqrt(3.0) * unitMm > toleranceMm / 50.0) ++d;
    return d;
  };
  return Decimals{needed(1.0, 3), needed(25.4, 4)};
}

double defaultCheckStepMm(const OffsetField& field) noexcept {
  return std::clamp(field.smallestNodeSpacingMm() / 4.0, 0.1, 5.0);
}

struct Compensator::Impl {
  Impl(OffsetField& f, CompensateOptions o, std::optional<Vec3> start)
      : field(f), options(o), tolerance(o.toleranceMm) {
    checkStep = options.checkStepMm > 0.0 ? options.checkStepMm : defaultCheckStepMm(field);
    bidirectional = field.bidirectionalAxes();
    if (start) {
      controller = *start;
      controllerKnown = true;
    }
  }

  OffsetField& field;
  CompensateOptions options;
  double tolerance;
  double checkStep = 1.0;
  std::string file;  ///< the program, for messages
  std::uint8_t bidirectional = 0;
  NcReport report;

  // Position of the machine as the written program leaves it (mm) and whether it is a
  // compensated vertex (a jump from it to a differing start is a reversal, not a lead-in).
  Vec3 controller = Vec3::Zero();
  bool controllerKnown = false;
  bool controllerCompensated = false;
  Directions lastDirs{};
  long compensatedMoves = 0;

  // Per chunk: points to solve, their results, and each motion's samples and sections.
  std::vector<Vec3> solveQ;
  std::vector<Directions> solveDirs;
  std::vector<long> solveLine;
  std::vector<OffsetSample> solveOut;
  std::vector<double> sampleU;
  std::vector<std::uint32_t> sampleRef;
  std::vector<Section> sections;
  std::vector<Planned> planned;
  std::int64_t prevEndRef = -1;
  Directions prevEndDirs{};
  std::vector<double> boundaries;
  std::vector<Piece> pieces;

  std::string out;
  Chunk chunk;

  // --- planning ---------------------------------------------------------------------------------

  Directions masked(Directions d) const {
    for (int k = 0; k < 3; ++k) {
      if ((bidirectional & (1u << k)) == 0) d[static_cast<std::size_t>(k)] = Direction::Unknown;
    }
    return d;
  }

  Directions lineDirections(const Move& m) const {
    Directions d = lastDirs;
    for (int k = 0; k < 3; ++k) {
      const Direction s = sign(m.endMm[k] - m.startMm[k]);
      if (s != Direction::Unknown) d[static_cast<std::size_t>(k)] = s;
    }
    return masked(d);
  }

  // Directions of travel along an arc at parameter u (derivative of the position), keeping the
  // last direction for axes that do not move.
  Directions arcDirections(const Move& m, double u, const Directions& previous) const {
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

  void addLineKinks(const Move& m) {
    for (int k = 0; k < 3; ++k) {
      const double a = m.startMm[k];
      const double delta = m.endMm[k] - a;
      if (delta == 0.0) continue;
      const std::vector<double>& kinks = field.kinks(k);
      const double lo = std::min(a, a + delta);
      const double hi = std::max(a, a + delta);
      for (auto it = std::upper_bound(kinks.begin(), kinks.end(), lo);
           it != kinks.end() && *it < hi; ++it) {
        boundaries.push_back((*it - a) / delta);
      }
    }
  }

  // Angles (as u) in the open sweep where the arc's coordinate along `axis` equals value, for
  // base solutions phi of the circle (the mean radius; a spiral moves them by its radius change).
  void addAngles(const ArcGeometry& a, double phi) {
    const double lo = std::min(a.startAngle, a.startAngle + a.sweep);
    const double hi = std::max(a.startAngle, a.startAngle + a.sweep);
    const double twoPi = 2.0 * kPi;
    for (double n = std::ceil((lo - phi) / twoPi); phi + n * twoPi < hi; n += 1.0) {
      const double theta = phi + n * twoPi;
      if (theta > lo) boundaries.push_back((theta - a.startAngle) / a.sweep);
    }
  }

  void addArcKinks(const Move& m) {
    const ArcGeometry& a = m.arc;
    const double radius = 0.5 * (a.startRadius + a.endRadius);
    if (radius <= 0.0 || a.sweep == 0.0) return;
    for (int which = 0; which < 2; ++which) {
      const int axis = which == 0 ? a.first : a.second;
      const double centre = which == 0 ? a.centerFirst : a.centerSecond;
      const std::vector<double>& kinks = field.kinks(axis);
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
      // Where the axis turns round (a bidirectional axis changes its direction there).
      if ((bidirectional & (1u << axis)) != 0) {
        addAngles(a, which == 0 ? 0.0 : kPi / 2);
        addAngles(a, which == 0 ? kPi : -kPi / 2);
      }
    }
    const double delta = a.endNormal - a.startNormal;
    if (delta != 0.0) {
      const std::vector<double>& kinks = field.kinks(a.normal);
      const double lo = std::min(a.startNormal, a.endNormal);
      const double hi = std::max(a.startNormal, a.endNormal);
      for (auto it = std::upper_bound(kinks.begin(), kinks.end(), lo);
           it != kinks.end() && *it < hi; ++it) {
        boundaries.push_back((*it - a.startNormal) / delta);
      }
    }
  }

  /// Throws NcError for a move whose start or end lies beyond kMaxPositionMm, in machine
  /// coordinates or in the frame its coordinates are written in (a work offset of 1e308 mm).
  void refuseOutOfRange(const MotionWork& w) const {
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
        throw NcError(file, w.line, 0, message.str());
      }
    };
    check(w.move.endMm, w.after);
    if (w.startKnown) check(w.move.startMm, w.before);
  }

  /// Throws NcError for a move that would need more than options.maxCheckPointsPerMove.
  void refuseOversized(const MotionWork& w) const {
    const Move& m = w.move;
    double needed = m.lengthMm() / checkStep;
    if (m.kind == MoveKind::Arc) {
      const double radius = std::max(m.arc.startRadius, m.arc.endRadius);
      if (radius > 0.5 * tolerance) {
        needed += 2.0 * std::abs(m.arc.sweep) / (2.0 * std::acos(1.0 - 0.5 * tolerance / radius));
      }
    }
    const double most = static_cast<double>(options.maxCheckPointsPerMove);
    if (needed <= most) return;  // also refuses NaN
    std::ostringstream message;
    message << "a move of " << m.lengthMm() << " mm needs about " << needed
            << " check points at the check step of " << checkStep << " mm, more than the "
            << options.maxCheckPointsPerMove
            << " one move may have (is the program in the machine's units?)";
    throw NcError(file, w.line, 0, message.str());
  }

  std::uint32_t addSolve(const Vec3& q, const Directions& d, long line) {
    solveQ.push_back(q);
    solveDirs.push_back(d);
    solveLine.push_back(line);
    return static_cast<std::uint32_t>(solveQ.size() - 1);
  }

  void addSample(double u, std::uint32_t ref) {
    sampleU.push_back(u);
    sampleRef.push_back(ref);
  }

  void plan(const MotionWork& w) {
    Planned p;
    p.sampleBegin = static_cast<std::uint32_t>(sampleU.size());
    p.sectionBegin = static_cast<std::uint32_t>(sections.size());
    const Move& m = w.move;
    if (!w.endKnown) {
      // Copied unchanged: where the machine is afterwards is not known to us.
      prevEndRef = -1;
      p.sampleEnd = p.sampleBegin;
      p.sectionEnd = p.sectionBegin;
      planned.push_back(p);
      return;
    }
    refuseOutOfRange(w);
    if (m.kind == MoveKind::Rapid || !w.startKnown) {
      Directions d = w.startKnown ? lineDirections(m) : masked(lastDirs);
      const std::uint32_t ref = addSolve(m.endMm, d, w.line);
      addSample(1.0, ref);
      lastDirs = d;
      prevEndRef = ref;
      prevEndDirs = d;
      p.sampleEnd = static_cast<std::uint32_t>(sampleU.size());
      p.sectionEnd = p.sectionBegin;
      planned.push_back(p);
      return;
    }
    p.split = true;
    refuseOversized(w);
    boundaries.clear();
    boundaries.push_back(0.0);
    if (m.kind == MoveKind::Line) {
      addLineKinks(m);
    } else {
      addArcKinks(m);
    }
    boundaries.push_back(1.0);
    std::sort(boundaries.begin(), boundaries.end());
    // Boundaries closer than 1e-9, or than a tenth of the tolerance along the move, to the
    // previous one (or to the end) are dropped. An arc whose end is an axis' extremum, written
    // with a few decimals, passes it by a few tens of nanometres of path, in which the axis
    // moves back by picometres: that is no reversal (a machine does not turn its direction for
    // that), and a section there would write two and compensate the next move, if that axis
    // stands still in it, with the wrong direction.
    {
      const double gap = std::max(1e-9, 0.1 * tolerance / std::max(m.lengthMm(), 1e-12));
      std::size_t kept = 1;
      for (std::size_t i = 1; i + 1 < boundaries.size(); ++i) {
        if (boundaries[i] > boundaries[kept - 1] + gap && boundaries[i] < 1.0 - gap) {
          boundaries[kept++] = boundaries[i];
        }
      }
      boundaries[kept++] = 1.0;
      boundaries.resize(kept);
    }
    const double length = m.lengthMm();
    Directions dirs = m.kind == MoveKind::Line ? lineDirections(m) : lastDirs;
    const Directions startDirs =
        m.kind == MoveKind::Line ? dirs : arcDirections(m, 0.5 * boundaries[1], lastDirs);
    // Start sample: the previous move's end when the directions agree.
    if (prevEndRef >= 0 && prevEndDirs == startDirs) {
      addSample(0.0, static_cast<std::uint32_t>(prevEndRef));
    } else {
      addSample(0.0, addSolve(m.startMm, startDirs, w.line));
    }
    dirs = startDirs;
    for (std::size_t b = 0; b + 1 < boundaries.size(); ++b) {
      const double u0 = boundaries[b];
      const double u1 = boundaries[b + 1];
      Directions d = m.kind == MoveKind::Line ? dirs : arcDirections(m, 0.5 * (u0 + u1), dirs);
      const bool hard = d != dirs;
      if (hard) {
        // The left end keeps the old directions (already sampled); the right side starts anew.
        addSample(u0, addSolve(m.at(u0), d, w.line));
      }
      dirs = d;
      // Arcs: pieces short enough for the circle's own sagitta (half the tolerance).
      int arcPieces = 1;
      if (m.kind == MoveKind::Arc) {
        const double radius = std::max(m.arc.startRadius, m.arc.endRadius);
        const double sweep = std::abs(m.arc.sweep) * (u1 - u0);
        if (radius > 0.5 * tolerance) {
          const double maxAngle = 2.0 * std::acos(1.0 - 0.5 * tolerance / radius);
          arcPieces = std::max(1, static_cast<int>(std::ceil(sweep / maxAngle)));
        }
      }
      for (int piece = 0; piece < arcPieces; ++piece) {
        const double a = u0 + (u1 - u0) * piece / arcPieces;
        const double e = piece + 1 == arcPieces ? u1 : u0 + (u1 - u0) * (piece + 1) / arcPieces;
        Section s;
        s.first = static_cast<std::uint32_t>(sampleU.size() - 1 - p.sampleBegin);
        s.dirs = d;
        s.hardStart = hard && piece == 0;
        const int intervals =
            std::max(2, static_cast<int>(std::ceil(length * (e - a) / checkStep)));
        for (int j = 1; j < intervals; ++j) {
          const double u = a + (e - a) * j / intervals;
          addSample(u, addSolve(m.at(u), d, w.line));
        }
        addSample(e, addSolve(m.at(e), d, w.line));
        s.last = static_cast<std::uint32_t>(sampleU.size() - 1 - p.sampleBegin);
        sections.push_back(s);
      }
    }
    lastDirs = dirs;
    prevEndRef = sampleRef.back();
    prevEndDirs = dirs;
    p.sampleEnd = static_cast<std::uint32_t>(sampleU.size());
    p.sectionEnd = static_cast<std::uint32_t>(sections.size());
    planned.push_back(p);
  }

  // --- solving ----------------------------------------------------------------------------------

  void solveAll() {
    solveOut.resize(solveQ.size());
    field.solve(solveQ, solveDirs, solveOut);
    report.offsetSolves += static_cast<long>(solveQ.size());
    for (std::size_t i = 0; i < solveOut.size(); ++i) note(solveOut[i], solveLine[i]);
  }

  void note(const OffsetSample& s, long line) {
    if (s.clampedAxes != 0) {
      ++report.outsideTravel;
      NcReport::list(report.outsideTravelLines, line, s.clampedAxes);
    }
    if (!s.converged) {
      ++report.notConverged;
      NcReport::list(report.notConvergedLines, line);
    }
  }

  Vec3 compensated(std::uint32_t ref) const { return solveQ[ref] + solveOut[ref].offsetMm; }

  // --- printing ---------------------------------------------------------------------------------

  static Printed print(const PrintMode& mode, const Vec3& targetMm, const Vec3& controllerMm) {
    const double unit = mode.frame.unitMm;
    const Vec3 shift = mode.machineCoordinates ? Vec3::Zero() : mode.frame.shiftMm;
    const double scale = pow10(mode.decimals);
    Printed p;
    for (int k = 0; k < 3; ++k) {
      const double target = (targetMm[k] - shift[k]) / unit;
      double written = 0.0;
      if (mode.incremental) {
        const double current = (controllerMm[k] - shift[k]) / unit;
        const std::int64_t inc = std::llround((target - current) * scale);
        p.counts[static_cast<std::size_t>(k)] = inc;
        written = current + static_cast<double>(inc) / scale;
      } else {
        const std::int64_t c = std::llround(target * scale);
        p.counts[static_cast<std::size_t>(k)] = c;
        written = static_cast<double>(c) / scale;
      }
      p.machineMm[k] = written * unit + shift[k];
    }
    return p;
  }

  static bool moves(const PrintMode& mode, const Printed& p, const Vec3& controllerMm) {
    if (mode.incremental) return p.counts != std::array<std::int64_t, 3>{};
    const Printed here = print(mode, controllerMm, controllerMm);
    return here.counts != p.counts;
  }

  void vertex(const OffsetSample& s) {
    ++report.vertices;
    const double o = s.offsetMm.norm();
    report.peakOffsetMm = std::max(report.peakOffsetMm, o);
    report.sumSqOffsetMm += o * o;
  }

  void emit(const PrintMode& mode, const Printed& p, PieceKind kind) {
    pieces.push_back(Piece{p.counts, kind, &mode});
    controller = p.machineMm;
    controllerKnown = true;
    controllerCompensated = true;
  }

  // --- checking and splitting -------------------------------------------------------------------
  //
  // A move is assembled from sections (samples uniformly spaced in u, both ends included). The
  // greedy takes as many sections into one piece as the check allows; a section that fails on its
  // own is replaced by finer sections (evaluated then) and the greedy goes on from there.

  struct WorkSample {
    double u = 0.0;
    Vec3 c = Vec3::Zero();  // exact compensated point
    OffsetSample offset;
  };
  struct WorkSection {
    std::uint32_t first = 0;  // samples [first, last] in `work`
    std::uint32_t last = 0;
    Directions dirs{};
    bool hardStart = false;
    int depth = 0;
    double allowanceMm = 0.0;
  };
  std::vector<WorkSample> work;
  std::vector<WorkSection> workSections;
  std::vector<WorkSection> finer;
  std::vector<Vec3> refineQ;
  std::vector<Directions> refineDirs;
  std::vector<OffsetSample> refineOut;
  std::vector<double> refineU;

  // Largest second difference / 8 of the section's samples: how far a curve with that curvature
  // can leave a straight piece between two neighbouring samples.
  double allowanceOf(const WorkSection& s) const {
    double worst = 0.0;
    for (std::uint32_t j = s.first + 1; j < s.last; ++j) {
      worst = std::max(worst, (work[j - 1].c - 2.0 * work[j].c + work[j + 1].c).norm());
    }
    return worst / 8.0;
  }

  void loadSections(const Planned& p) {
    work.clear();
    workSections.clear();
    for (std::uint32_t s = p.sectionBegin; s < p.sectionEnd; ++s) {
      const Section& sec = sections[s];
      WorkSection ws;
      ws.first = static_cast<std::uint32_t>(work.size());
      for (std::uint32_t j = sec.first; j <= sec.last; ++j) {
        const std::uint32_t ref = sampleRef[p.sampleBegin + j];
        work.push_back(WorkSample{sampleU[p.sampleBegin + j], compensated(ref), solveOut[ref]});
      }
      ws.last = static_cast<std::uint32_t>(work.size() - 1);
      ws.dirs = sec.dirs;
      ws.hardStart = sec.hardStart;
      ws.allowanceMm = allowanceOf(ws);
      workSections.push_back(ws);
    }
  }

  // Deviation of the samples of sections [a, b] from the piece vFrom -> vTo.
  double chordDeviation(std::size_t a, std::size_t b, const Vec3& vFrom, const Vec3& vTo,
                        long& checks) const {
    const double uFrom = work[workSections[a].first].u;
    const double span = work[workSections[b].last].u - uFrom;
    double worst = 0.0;
    for (std::size_t s = a; s <= b; ++s) {
      for (std::uint32_t j = workSections[s].first + (s == a ? 0 : 1); j <= workSections[s].last;
           ++j) {
        const double t = span > 0.0 ? (work[j].u - uFrom) / span : 0.0;
        worst = std::max(worst, (work[j].c - (vFrom + t * (vTo - vFrom))).norm());
        ++checks;
      }
    }
    return worst;
  }

  // Replaces section i by finer sections short enough to pass (deviation about 1/16 of the
  // tolerance each, so that the greedy can join them into pieces close to the longest possible).
  void subdivide(const MotionWork& w, std::size_t i, double bound) {
    const WorkSection s = workSections[i];
    const double u0 = work[s.first].u;
    const double u1 = work[s.last].u;
    const double lengthMm = w.move.lengthMm() * (u1 - u0);
    // Clamped as a double: the cast of an infinite or NaN bound to int is undefined.
    const double wanted = std::ceil(std::sqrt(bound / (tolerance / 16.0)));
    const int m = wanted >= 1024.0 ? 1024 : wanted >= 2.0 ? static_cast<int>(wanted) : 2;
    const int intervals = std::max(2, static_cast<int>(std::ceil(lengthMm / m / checkStep)));
    refineQ.clear();
    refineU.clear();
    for (int j = 0; j < m; ++j) {
      for (int k = 1; k <= intervals; ++k) {
        if (j + 1 == m && k == intervals) break;  // the section's own end is known
        const double u =
            u0 + (u1 - u0) * (j * intervals + k) / (static_cast<double>(m) * intervals);
        refineU.push_back(u);
        refineQ.push_back(w.move.at(u));
      }
    }
    refineDirs.assign(refineQ.size(), s.dirs);
    refineOut.resize(refineQ.size());
    const auto t0 = Clock::now();
    field.solve(refineQ, refineDirs, refineOut);
    report.offsetSolves += static_cast<long>(refineQ.size());
    report.offsetsS += seconds(t0, Clock::now());
    finer.clear();
    std::size_t next = 0;
    for (int j = 0; j < m; ++j) {
      WorkSection f;
      f.dirs = s.dirs;
      f.hardStart = j == 0 && s.hardStart;
      f.depth = s.depth + 1;
      f.first = static_cast<std::uint32_t>(work.size());
      const WorkSample start = j == 0 ? work[s.first] : work[finer.back().last];
      work.push_back(start);
      for (int k = 1; k <= intervals; ++k) {
        if (j + 1 == m && k == intervals) {
          const WorkSample end = work[s.last];
          work.push_back(end);
          break;
        }
        note(refineOut[next], w.line);
        work.push_back(
            WorkSample{refineU[next], refineQ[next] + refineOut[next].offsetMm, refineOut[next]});
        ++next;
      }
      f.last = static_cast<std::uint32_t>(work.size() - 1);
      f.allowanceMm = allowanceOf(f);
      finer.push_back(f);
    }
    workSections.erase(workSections.begin() + static_cast<std::ptrdiff_t>(i));
    workSections.insert(workSections.begin() + static_cast<std::ptrdiff_t>(i), finer.begin(),
                        finer.end());
  }

  void accept(double deviation, double bound, long checks) {
    report.maxDeviationMm = std::max(report.maxDeviationMm, deviation);
    report.maxBoundMm = std::max(report.maxBoundMm, bound);
    report.checkPoints += checks;
  }

  // Writes the pieces of a planned feed move.
  void assemble(const MotionWork& w, const Planned& p) {
    loadSections(p);
    // The compensated start (with this move's directions) may differ from where the machine is.
    {
      const Printed start = print(w.before, work[workSections[0].first].c, controller);
      if (moves(w.before, start, controller)) {
        const PieceKind kind = controllerCompensated ? PieceKind::Reversal : PieceKind::LeadIn;
        if (kind == PieceKind::Reversal) ++report.reversalMoves;
        emit(w.before, start, kind);
      }
    }
    std::size_t i = 0;
    while (i < workSections.size()) {
      if (i > 0 && workSections[i].hardStart) {
        const Printed start = print(w.after, work[workSections[i].first].c, controller);
        if (moves(w.after, start, controller)) {
          ++report.reversalMoves;
          emit(w.after, start, PieceKind::Reversal);
        }
      }
      std::size_t best = workSections.size();
      Printed bestPrinted;
      double bestDeviation = 0.0, bestBound = 0.0, allowanceMax = 0.0, failedBound = 0.0;
      long bestChecks = 0;
      for (std::size_t b = i; b < workSections.size() && (b == i || !workSections[b].hardStart);
           ++b) {
        const Printed end = print(w.after, work[workSections[b].last].c, controller);
        allowanceMax = std::max(allowanceMax, workSections[b].allowanceMm);
        long checks = 0;
        const double deviation = chordDeviation(i, b, controller, end.machineMm, checks);
        const double bound = deviation + allowanceMax;
        if (bound > tolerance) {
          failedBound = bound;
          break;
        }
        best = b;
        bestPrinted = end;
        bestDeviation = deviation;
        bestBound = bound;
        bestChecks = checks;
      }
      if (best == workSections.size()) {
        const WorkSection& s = workSections[i];
        const double lengthMm = w.move.lengthMm() * (work[s.last].u - work[s.first].u);
        if (s.depth < kMaxRefineDepth && lengthMm > kMinPieceMm) {
          subdivide(w, i, failedBound);
          continue;
        }
        // Nothing shorter helps (a jump in the offset): the piece is kept and reported.
        ++report.unresolvedPieces;
        best = i;
        bestPrinted = print(w.after, work[s.last].c, controller);
        bestBound = failedBound;
        bestDeviation = chordDeviation(i, i, controller, bestPrinted.machineMm, bestChecks);
      }
      accept(bestDeviation, bestBound, bestChecks);
      vertex(work[workSections[best].last].offset);
      emit(w.after, bestPrinted, PieceKind::Normal);
      i = best + 1;
    }
  }

  // --- writing ----------------------------------------------------------------------------------

  void appendMotion(std::string& text, const Piece& piece, bool rapid) {
    if (piece.mode->machineCoordinates) text += "G53 ";
    text += rapid ? "G0" : "G1";
    static constexpr char kAxes[3] = {'X', 'Y', 'Z'};
    for (int k = 0; k < 3; ++k) {
      text += ' ';
      text += kAxes[k];
      appendCounts(text, piece.counts[static_cast<std::size_t>(k)], piece.mode->decimals);
    }
  }

  void line(std::string_view text, std::string_view eol) {
    out.append(text);
    out.append(eol.empty() ? std::string_view("\n") : eol);
    report.linesOut += 1 + static_cast<long>(std::count(text.begin(), text.end(), '\n'));
  }

  void writeMotion(const LineWork& lw, const MotionWork& w) {
    const bool rapid = w.move.kind == MoveKind::Rapid;
    std::size_t i = 0;
    std::string text;
    // Lines that reach the compensated start come before the line itself.
    while (i < pieces.size() && pieces[i].kind != PieceKind::Normal) {
      text.clear();
      appendMotion(text, pieces[i], false);
      if (w.feed.size > 0) {
        text += ' ';
        text += chunk.view(w.feed);
      }
      text += pieces[i].kind == PieceKind::Reversal ? " (volcomp: reversal)"
                                                    : " (volcomp: to the compensated start)";
      line(text, lw.eol);
      ++i;
    }
    text.assign(chunk.view(w.prefix));
    appendMotion(text, pieces[i], rapid);
    text += chunk.view(w.suffix);
    line(text, lw.eol);
    ++report.motionLinesOut;
    for (++i; i < pieces.size(); ++i) {
      text.clear();
      appendMotion(text, pieces[i], rapid);
      if (pieces[i].kind == PieceKind::Reversal) text += " (volcomp: reversal)";
      line(text, lw.eol);
      if (pieces[i].kind == PieceKind::Normal) ++report.motionLinesOut;
    }
    if (w.tail.size > 0) line(chunk.view(w.tail), lw.eol);
  }

  void countMove(const Move& m) {
    if (m.kind == MoveKind::Rapid) ++report.rapidMoves;
    if (m.kind == MoveKind::Line) ++report.feedMoves;
    if (m.kind == MoveKind::Arc) ++report.arcMoves;
  }

  void processChunk(TextSink& sink) {
    auto t0 = Clock::now();
    solveQ.clear();
    solveDirs.clear();
    solveLine.clear();
    sampleU.clear();
    sampleRef.clear();
    sections.clear();
    planned.clear();
    prevEndRef = -1;
    for (const MotionWork& w : chunk.motions) plan(w);
    auto t1 = Clock::now();
    report.splitS += seconds(t0, t1);
    solveAll();
    auto t2 = Clock::now();
    report.offsetsS += seconds(t1, t2);
    double assembleS = 0.0;
    const double offsetsAtLoop = report.offsetsS;
    for (const LineWork& lw : chunk.lines) {
      switch (lw.action) {
        case LineAction::Copy:
          line(lw.input, lw.eol);
          break;
        case LineAction::Drop:
          break;
        case LineAction::Text:
          line(chunk.view(lw.text), lw.eol);
          break;
        case LineAction::Motion: {
          const MotionWork& w = chunk.motions[lw.motion];
          const Planned& p = planned[lw.motion];
          countMove(w.move);
          if (!w.endKnown) {
            ++report.uncompensatedMoves;
            NcReport::list(report.uncompensatedLines, w.line);
            line(lw.input, lw.eol);
            break;
          }
          ++compensatedMoves;
          pieces.clear();
          const double offsetsBefore = report.offsetsS;
          const auto ta = Clock::now();
          if (!p.split) {
            if (!w.startKnown && w.move.kind != MoveKind::Rapid) {
              ++report.endOnlyMoves;
              NcReport::list(report.endOnlyLines, w.line);
            }
            const std::uint32_t ref = sampleRef[p.sampleBegin];
            vertex(solveOut[ref]);
            emit(w.after, print(w.after, compensated(ref), controller), PieceKind::Normal);
          } else {
            assemble(w, p);
          }
          assembleS += seconds(ta, Clock::now()) - (report.offsetsS - offsetsBefore);
          writeMotion(lw, w);
          break;
        }
      }
    }
    report.splitS += assembleS;
    sink.write(out);
    out.clear();
    report.writeS += seconds(t2, Clock::now()) - assembleS - (report.offsetsS - offsetsAtLoop);
  }
};

Compensator::Compensator(OffsetField& field, CompensateOptions options, std::optional<Vec3> startMm)
    : impl_(std::make_unique<Impl>(field, options, startMm)) {}

Compensator::~Compensator() = default;

NcReport Compensator::run(ProgramReader& reader, TextSource& source, TextSink& sink,
                          const ProgressFn& progress) {
  Impl& s = *impl_;
  const auto start = Clock::now();
  NcReport& r = s.report;
  r.format = reader.formatName();
  s.file = reader.file();
  r.toleranceMm = s.tolerance;
  r.checkStepMm = s.checkStep;
  s.out.clear();
  reader.header(s.out);
  for (char c : s.out) r.linesOut += c == '\n' ? 1 : 0;
  long number = 0;
  while (true) {
    const std::string_view text = source.nextLines();
    if (text.empty()) break;
    std::size_t pos = 0;
    while (pos < text.size()) {
      const auto t0 = Clock::now();
      s.chunk.clear();
      while (pos < text.size() && s.chunk.lines.size() < s.options.chunkLines) {
        const std::size_t nl = text.find('\n', pos);
        const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
        std::string_view lineText = text.substr(pos, end - pos);
        std::string_view eol =
            nl == std::string_view::npos ? std::string_view() : text.substr(nl, 1);
        if (!lineText.empty() && lineText.back() == '\r') {
          lineText.remove_suffix(1);
          eol = nl == std::string_view::npos ? text.substr(end - 1, 1) : text.substr(nl - 1, 2);
        }
        reader.read(lineText, eol, ++number, s.chunk);
        pos = nl == std::string_view::npos ? text.size() : nl + 1;
      }
      r.readS += seconds(t0, Clock::now());
      s.processChunk(sink);
      r.linesIn = number;
      if (progress) progress(source.bytesRead(), source.totalBytes(), number);
    }
  }
  reader.trailer(s.out);
  for (char c : s.out) r.linesOut += c == '\n' ? 1 : 0;
  sink.write(s.out);
  sink.flush();
  r.linesIn = number;
  r.piecesAdded = r.motionLinesOut - s.compensatedMoves;
  r.timeS = seconds(start, Clock::now());
  return r;
}

double NcReport::rmsOffsetMm() const {
  return vertices > 0 ? std::sqrt(sumSqOffsetMm / static_cast<double>(vertices)) : 0.0;
}

void NcReport::list(std::vector<ListedLine>& lines, long line, std::uint8_t axes) {
  if (!lines.empty() && lines.back().line == line) {
    lines.back().axes |= axes;
    return;
  }
  if (lines.size() < kMaxListed) lines.push_back(ListedLine{line, axes});
}

}  // namespace volcomp::nc
