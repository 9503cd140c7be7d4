#include "volcomp/nc/compensator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "compensation_tally.hpp"
#include "motion_writer.hpp"
#include "move_planner.hpp"
#include "move_refiner.hpp"
#include "printed_path.hpp"

namespace volcomp::nc {

using detail::Clock;
using detail::seconds;

Decimals decimalsForTolerance(double toleranceMm) noexcept {
  // Rounding each coordinate by half a unit of the last decimal moves a point
  // by at most 0.5 * 10^-d * sqrt(3) units.
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

// The stages of a chunk, each in a part of its own: plan where to solve
// (MovePlanner), solve all points at once, then per line check and split the
// move (MoveRefiner) on the path as printed (PrintedPath) and write it
// (MotionWriter).
struct Compensator::Impl {
  Impl(OffsetField& f, CompensateOptions o, std::optional<Vec3> start)
      : field(f),
        options(o),
        tolerance(o.toleranceMm),
        checkStep(o.checkStepMm > 0.0 ? o.checkStepMm : defaultCheckStepMm(f)),
        planner(f, tolerance, checkStep, o.maxCheckPointsPerMove, file),
        refiner(f, tolerance, checkStep, report),
        writer(report) {
    if (start) {
      path.controller = *start;
      path.controllerKnown = true;
    }
  }

  OffsetField& field;
  CompensateOptions options;
  double tolerance;
  double checkStep;
  std::string file;  ///< the program, for messages
  NcReport report;
  long compensatedMoves = 0;

  detail::ChunkPlan plan;
  detail::MovePlanner planner;
  detail::PrintedPath path;
  detail::MoveRefiner refiner;
  detail::MotionWriter writer;
  Chunk chunk;

  void solveAll() {
    plan.solveOut.resize(plan.solveQ.size());
    field.solve(plan.solveQ, plan.solveDirs, plan.solveOut);
    report.offsetSolves += static_cast<long>(plan.solveQ.size());
    for (std::size_t i = 0; i < plan.solveOut.size(); ++i) {
      detail::noteSolved(report, plan.solveOut[i], plan.solveLine[i]);
    }
  }

  void countMove(const Move& m) {
    if (m.kind == MoveKind::Rapid) ++report.rapidMoves;
    if (m.kind == MoveKind::Line) ++report.feedMoves;
    if (m.kind == MoveKind::Arc) ++report.arcMoves;
  }

  // The pieces of a compensated move: its end point only, or the checked and
  // split path.
  void compensate(const MotionWork& w, const detail::Planned& p) {
    path.pieces.clear();
    if (p.split) {
      refiner.assemble(w, p, plan, path);
      return;
    }
    if (!w.startKnown && w.move.kind != MoveKind::Rapid) {
      ++report.endOnlyMoves;
      NcReport::list(report.endOnlyLines, w.line);
    }
    const std::uint32_t ref = plan.sampleRef[p.sampleBegin];
    detail::noteVertex(report, plan.solveOut[ref]);
    path.emit(w.after, path.next(w.after, plan.compensated(ref)), detail::PieceKind::Normal);
  }

  void processChunk(TextSink& sink) {
    auto t0 = Clock::now();
    planner.startChunk(plan);
    for (const MotionWork& w : chunk.motions) planner.plan(w, plan);
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
          writer.line(lw.input, lw.eol);
          break;
        case LineAction::Drop:
          break;
        case LineAction::Text:
          writer.line(chunk.view(lw.text), lw.eol);
          break;
        case LineAction::Motion: {
          const MotionWork& w = chunk.motions[lw.motion];
          countMove(w.move);
          if (!w.endKnown) {
            ++report.uncompensatedMoves;
            NcReport::list(report.uncompensatedLines, w.line);
            writer.line(lw.input, lw.eol);
            break;
          }
          ++compensatedMoves;
          // Refinement solves are counted as offsets, not as planning.
          const double offsetsBefore = report.offsetsS;
          const auto ta = Clock::now();
          compensate(w, plan.planned[lw.motion]);
          assembleS += seconds(ta, Clock::now()) - (report.offsetsS - offsetsBefore);
          writer.writeMotion(lw, w, path.pieces, chunk);
          break;
        }
      }
    }
    report.splitS += assembleS;
    sink.write(writer.out);
    writer.out.clear();
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
  s.writer.out.clear();
  reader.header(s.writer.out);
  for (char c : s.writer.out) r.linesOut += c == '\n' ? 1 : 0;
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
  reader.trailer(s.writer.out);
  for (char c : s.writer.out) r.linesOut += c == '\n' ? 1 : 0;
  sink.write(s.writer.out);
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
