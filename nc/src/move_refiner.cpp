#include "move_refiner.hpp"

#include <algorithm>
#include <cmath>

#include "compensation_tally.hpp"

namespace volcomp::nc::detail {
namespace {

constexpr int kMaxRefineDepth = 12;
constexpr double kMinPieceMm = 1e-7;

}  // namespace

// A move is assembled from sections (samples uniformly spaced in u, both ends
// included). The greedy takes as many sections into one piece as the check
// allows; a section that fails on its own is replaced by finer sections
// (evaluated then) and the greedy goes on from there.

MoveRefiner::MoveRefiner(OffsetField& field, double toleranceMm, double checkStepMm,
                         NcReport& report)
    : field_(field), tolerance_(toleranceMm), checkStep_(checkStepMm), report_(report) {}

// Largest second difference / 8 of the section's samples: how far a curve with
// that curvature can leave a straight piece between two neighbouring samples.
double MoveRefiner::allowanceOf(const WorkSection& s) const {
  double worst = 0.0;
  for (std::uint32_t j = s.first + 1; j < s.last; ++j) {
    worst = std::max(worst, (work_[j - 1].c - 2.0 * work_[j].c + work_[j + 1].c).norm());
  }
  return worst / 8.0;
}

void MoveRefiner::loadSections(const Planned& p, const ChunkPlan& plan) {
  work_.clear();
  workSections_.clear();
  for (std::uint32_t s = p.sectionBegin; s < p.sectionEnd; ++s) {
    const Section& sec = plan.sections[s];
    WorkSection ws;
    ws.first = static_cast<std::uint32_t>(work_.size());
    for (std::uint32_t j = sec.first; j <= sec.last; ++j) {
      const std::uint32_t ref = plan.sampleRef[p.sampleBegin + j];
      work_.push_back(
          WorkSample{plan.sampleU[p.sampleBegin + j], plan.compensated(ref), plan.solveOut[ref]});
    }
    ws.last = static_cast<std::uint32_t>(work_.size() - 1);
    ws.dirs = sec.dirs;
    ws.hardStart = sec.hardStart;
    ws.allowanceMm = allowanceOf(ws);
    workSections_.push_back(ws);
  }
}

// Deviation of the samples of sections [a, b] from the piece vFrom -> vTo.
double MoveRefiner::chordDeviation(std::size_t a, std::size_t b, const Vec3& vFrom, const Vec3& vTo,
                                   long& checks) const {
  const double uFrom = work_[workSections_[a].first].u;
  const double span = work_[workSections_[b].last].u - uFrom;
  double worst = 0.0;
  for (std::size_t s = a; s <= b; ++s) {
    for (std::uint32_t j = workSections_[s].first + (s == a ? 0 : 1); j <= workSections_[s].last;
         ++j) {
      const double t = span > 0.0 ? (work_[j].u - uFrom) / span : 0.0;
      worst = std::max(worst, (work_[j].c - (vFrom + t * (vTo - vFrom))).norm());
      ++checks;
    }
  }
  return worst;
}

// Replaces section i by finer sections short enough to pass (deviation about
// 1/16 of the tolerance each, so that the greedy can join them into pieces
// close to the longest possible).
void MoveRefiner::subdivide(const MotionWork& w, std::size_t i, double bound) {
  const WorkSection s = workSections_[i];
  const double u0 = work_[s.first].u;
  const double u1 = work_[s.last].u;
  const double lengthMm = w.move.lengthMm() * (u1 - u0);
  // Clamped as a double: the cast of an infinite or NaN bound to int is
  // undefined.
  const double wanted = std::ceil(std::sqrt(bound / (tolerance_ / 16.0)));
  const int m = wanted >= 1024.0 ? 1024 : wanted >= 2.0 ? static_cast<int>(wanted) : 2;
  const int intervals = std::max(2, static_cast<int>(std::ceil(lengthMm / m / checkStep_)));
  refineQ_.clear();
  refineU_.clear();
  for (int j = 0; j < m; ++j) {
    for (int k = 1; k <= intervals; ++k) {
      if (j + 1 == m && k == intervals) break;  // the section's own end is known
      const double u = u0 + (u1 - u0) * (j * intervals + k) / (static_cast<double>(m) * intervals);
      refineU_.push_back(u);
      refineQ_.push_back(w.move.at(u));
    }
  }
  refineDirs_.assign(refineQ_.size(), s.dirs);
  refineOut_.resize(refineQ_.size());
  const auto t0 = Clock::now();
  field_.solve(refineQ_, refineDirs_, refineOut_);
  report_.offsetSolves += static_cast<long>(refineQ_.size());
  report_.offsetsS += seconds(t0, Clock::now());
  finer_.clear();
  std::size_t next = 0;
  for (int j = 0; j < m; ++j) {
    WorkSection f;
    f.dirs = s.dirs;
    f.hardStart = j == 0 && s.hardStart;
    f.depth = s.depth + 1;
    f.first = static_cast<std::uint32_t>(work_.size());
    const WorkSample start = j == 0 ? work_[s.first] : work_[finer_.back().last];
    work_.push_back(start);
    for (int k = 1; k <= intervals; ++k) {
      if (j + 1 == m && k == intervals) {
        const WorkSample end = work_[s.last];
        work_.push_back(end);
        break;
      }
      noteSolved(report_, refineOut_[next], w.line);
      work_.push_back(
          WorkSample{refineU_[next], refineQ_[next] + refineOut_[next].offsetMm, refineOut_[next]});
      ++next;
    }
    f.last = static_cast<std::uint32_t>(work_.size() - 1);
    f.allowanceMm = allowanceOf(f);
    finer_.push_back(f);
  }
  workSections_.erase(workSections_.begin() + static_cast<std::ptrdiff_t>(i));
  workSections_.insert(workSections_.begin() + static_cast<std::ptrdiff_t>(i), finer_.begin(),
                       finer_.end());
}

void MoveRefiner::accept(double deviation, double bound, long checks) {
  report_.maxDeviationMm = std::max(report_.maxDeviationMm, deviation);
  report_.maxBoundMm = std::max(report_.maxBoundMm, bound);
  report_.checkPoints += checks;
}

MoveRefiner::Candidate MoveRefiner::longestPiece(const MotionWork& w, std::size_t i,
                                                 const PrintedPath& path) const {
  Candidate best;
  best.best = workSections_.size();
  double allowanceMax = 0.0;
  for (std::size_t b = i; b < workSections_.size() && (b == i || !workSections_[b].hardStart);
       ++b) {
    const Printed end = path.next(w.after, work_[workSections_[b].last].c);
    allowanceMax = std::max(allowanceMax, workSections_[b].allowanceMm);
    long checks = 0;
    const double deviation = chordDeviation(i, b, path.controller, end.machineMm, checks);
    const double bound = deviation + allowanceMax;
    if (bound > tolerance_) {
      best.failedBound = bound;
      break;
    }
    best.best = b;
    best.printed = end;
    best.deviation = deviation;
    best.bound = bound;
    best.checks = checks;
  }
  return best;
}

void MoveRefiner::assemble(const MotionWork& w, const Planned& p, const ChunkPlan& plan,
                           PrintedPath& path) {
  loadSections(p, plan);
  // The compensated start (with this move's directions) may differ from where
  // the machine is.
  if (path.jumpTo(w.before, work_[workSections_[0].first].c, false)) ++report_.reversalMoves;
  std::size_t i = 0;
  while (i < workSections_.size()) {
    if (i > 0 && workSections_[i].hardStart &&
        path.jumpTo(w.after, work_[workSections_[i].first].c, true)) {
      ++report_.reversalMoves;
    }
    Candidate piece = longestPiece(w, i, path);
    if (piece.best == workSections_.size()) {
      const WorkSection& s = workSections_[i];
      const double lengthMm = w.move.lengthMm() * (work_[s.last].u - work_[s.first].u);
      if (s.depth < kMaxRefineDepth && lengthMm > kMinPieceMm) {
        subdivide(w, i, piece.failedBound);
        continue;
      }
      // Nothing shorter helps (a jump in the offset): the piece is kept and
      // reported.
      ++report_.unresolvedPieces;
      piece.best = i;
      piece.printed = path.next(w.after, work_[s.last].c);
      piece.bound = piece.failedBound;
      piece.deviation =
          chordDeviation(i, i, path.controller, piece.printed.machineMm, piece.checks);
    }
    accept(piece.deviation, piece.bound, piece.checks);
    noteVertex(report_, work_[workSections_[piece.best].last].offset);
    path.emit(w.after, piece.printed, PieceKind::Normal);
    i = piece.best + 1;
  }
}

}  // namespace volcomp::nc::detail
