#pragma once
/// Offline compensation of an NC program, streamed chunk by chunk (memory does not grow with the
/// program).
///
/// Every programmed point p (tool tip, work coordinates) is at machine position q (see setup.hpp);
/// it is written as p' = p + o(q), o the model's compensation offset with the direction of travel
/// of the move. A straight or circular feed move becomes the ideal compensated curve
///   C(u) = q(u) + o(q(u)),  u in [0, 1] along the programmed move,
/// which is not straight; it is written as a polyline through vertices C(u_i) (rounded to the
/// printed decimals) such that at every check point the deviation
///   | C(u) - (V_i + t (V_i+1 - V_i)) |,  t = (u - u_i) / (u_i+1 - u_i),
/// of the written piece from the ideal curve (the same parameter on both) plus a curvature
/// allowance (largest second difference of C between neighbouring check points / 8, which bounds
/// how far a C2 curve can leave the piece between them) stays within the tolerance. Check points:
/// the ends of every piece, every kink of the offset along the move (offset_field.hpp), and points
/// at most the check step apart (at least the middle of every piece). Pieces are as long as this
/// allows (a move where o is affine stays one move). Rapids get their end point compensated
/// only: their path is the controller's. Where a bidirectional axis changes its direction of
/// travel the compensated point jumps (reversal value): a short "reversal" move at the vertex
/// (on a line of its own, "(volcomp: reversal)") takes it, as a backlash compensation would.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "volcomp/nc/ngc_interpreter.hpp"
#include "volcomp/nc/offset_field.hpp"
#include "volcomp/nc/program_lines.hpp"
#include "volcomp/nc/report.hpp"
#include "volcomp/nc/text_io.hpp"

namespace volcomp::nc {

struct CompensateOptions {
  double toleranceMm = 0.001;
  /// Largest distance between check points along a move (mm); 0 = a quarter of the smallest
  /// node spacing of the model's tables and grids, within [0.1, 5] mm.
  double checkStepMm = 0.0;
  /// Lines per chunk (the unit of streaming and of batched offset solves).
  std::size_t chunkLines = 4096;
  /// Check points one move may need (its length over the check step, plus the pieces an arc is
  /// split into for its sagitta); a move needing more is refused (NcError at its line). The
  /// default is a 100 m move at the smallest default check step: beyond it a program is almost
  /// certainly in the wrong units or garbled, and planning it would take minutes and gigabytes.
  std::size_t maxCheckPointsPerMove = 1000000;
};

/// Decimals to write so that rounding moves a point by at most tolerance / 50 (3 .. 9 for mm,
/// 4 .. 9 for inch).
Decimals decimalsForTolerance(double toleranceMm) noexcept;

/// Default check step for a model (see CompensateOptions::checkStepMm).
double defaultCheckStepMm(const OffsetField& field) noexcept;

/// (bytes read, bytes in total or 0, lines read): called after every chunk.
using ProgressFn = std::function<void(std::uint64_t, std::uint64_t, long)>;

class Compensator {
 public:
  /// `startMm`: machine position at the program start when known (else moves before every axis
  /// has been programmed are copied unchanged, and a feed move from an unknown start gets its
  /// end point only).
  Compensator(OffsetField& field, CompensateOptions options, std::optional<Vec3> startMm);
  ~Compensator();
  Compensator(const Compensator&) = delete;
  Compensator& operator=(const Compensator&) = delete;

  /// Reads the program from `source` with `reader`, writes the compensated program to `sink`.
  /// Throws NcError for a rejected line (nothing more is written then).
  NcReport run(ProgramReader& reader, TextSource& source, TextSink& sink,
               const ProgressFn& progress = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace volcomp::nc
