#pragma once
/// The path as the written program makes it: targets rounded to the printed
/// decimals in the frame and distance mode of their line, the pieces written
/// for the current move, and where the machine is after them (program-frame
/// bookkeeping of the compensator).

#include <array>
#include <cstdint>
#include <vector>

#include "volcomp/nc/interpreter_state.hpp"

namespace volcomp::nc::detail {

/// A point as written: the printed counts (units of the last decimal;
/// increments in G91) and the machine position they stand for.
struct Printed {
  Vec3 machineMm = Vec3::Zero();
  std::array<std::int64_t, 3> counts{};
};

/// Normal: a piece of the move; Reversal: the jump at a vertex where a
/// bidirectional axis turns (or where the compensated start differs from a
/// compensated end); LeadIn: to the compensated start from a position that was
/// not compensated.
enum class PieceKind : std::uint8_t { Normal, Reversal, LeadIn };

/// One motion line to write.
struct Piece {
  std::array<std::int64_t, 3> counts{};
  PieceKind kind = PieceKind::Normal;
  const PrintMode* mode = nullptr;
};

/// `targetMm` as written in `mode` by a line that starts at `controllerMm`.
Printed print(const PrintMode& mode, const Vec3& targetMm, const Vec3& controllerMm);

struct PrintedPath {
  // Position of the machine as the written program leaves it (mm) and whether
  // it is a compensated vertex (a jump from it to a differing start is a
  // reversal, not a lead-in).
  Vec3 controller = Vec3::Zero();
  bool controllerKnown = false;
  bool controllerCompensated = false;
  /// The pieces of the current move, in order.
  std::vector<Piece> pieces;

  /// `targetMm` as the next line written in `mode` would write it.
  Printed next(const PrintMode& mode, const Vec3& targetMm) const {
    return print(mode, targetMm, controller);
  }
  /// True when writing `p` in `mode` would move the machine (it differs in a
  /// printed digit).
  bool moves(const PrintMode& mode, const Printed& p) const;
  /// Appends a piece to `p` and moves the controller there.
  void emit(const PrintMode& mode, const Printed& p, PieceKind kind) {
    pieces.push_back(Piece{p.counts, kind, &mode});
    controller = p.machineMm;
    controllerKnown = true;
    controllerCompensated = true;
  }
  /// Writes a jump to `targetMm` when the machine is not there as printed: a
  /// reversal when the machine is at a compensated vertex, else a lead-in (or
  /// always a reversal with `alwaysReversal`, inside a move). Returns true when
  /// a reversal was written.
  bool jumpTo(const PrintMode& mode, const Vec3& targetMm, bool alwaysReversal);
};

}  // namespace volcomp::nc::detail
