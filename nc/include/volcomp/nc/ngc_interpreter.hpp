#pragma once
/// Reads RS274/NGC programs in the subset a CAM post-processor emits, line by line, as LinuxCNC
/// would: modal state, work offsets, tool offsets, and the move each line makes in machine axis
/// coordinates. Anything outside the subset is rejected (with the column of the word and what was
/// found), never guessed at.
///
/// Supported: G0 G1 G2 G3 (IJK and R forms, P turns, full circles, helices), G4, G17 G18 G19,
/// G20 G21, G40, G43 (H or the tool in the spindle) G43.1 G49, G53, G54 .. G59.3, G61 G61.1 G64,
/// G80, G90 G91, G90.1 G91.1, G94 G95, G96 G97, G98 G99; F S T N words; M0 M1 M2 M3 M4 M5 M6 M7
/// M8 M9 M19 M30 M48 .. M53 M60 M61 .. M68 M100 .. M199; comments. Rejected: parameters and
/// expressions, O-words, canned cycles (G73 G76 G81 .. G89), cutter radius compensation (G41
/// G42), G92 and G10 (offsets changed by the program), G28 G30, probing (G38.x), threading (G33),
/// splines (G5.x), inverse time (G93), lathe modes (G7), rotary and UVW axes, M70 .. M73.
///
/// Arcs follow LinuxCNC: the centre of an IJK arc comes from the start point (G91.1, the default)
/// or is absolute (G90.1); an R arc's centre is computed as LinuxCNC's arc_data_r does; an arc
/// whose end radius differs from its start radius by more than 0.02 mm (0.002 in) and 0.1 % is
/// rejected, a smaller difference is a spiral.

#include <cstdint>
#include <optional>

#include "volcomp/nc/block.hpp"
#include "volcomp/nc/interpreter_state.hpp"
#include "volcomp/nc/setup.hpp"

namespace volcomp::nc {

/// Number of decimals written for each unit.
struct Decimals {
  int mm = 5;
  int inch = 6;
};

/// What one line does, for the compensation and the writer.
struct NgcLine {
  bool motion = false;          ///< the line moves (G0, G1, G2, G3, possibly with G53)
  Move move;                    ///< machine coordinates, mm (valid when the start is known)
  bool startKnown = false;      ///< every axis of the start position is known
  bool endKnown = false;        ///< every axis of the end position is known
  PrintMode before;             ///< how coordinates are written before this line's modal changes
  PrintMode after;              ///< how the line's own coordinates are written
  bool programEnd = false;      ///< M2 / M30: nothing after this line runs
  std::uint64_t dropWords = 0;  ///< bit i: word i is replaced by the written motion
  std::uint64_t stopWords = 0;  ///< bit i: word i (M0 M1 M2 M30 M60) runs after the motion
  int feedWord = -1;            ///< index of the line's F word, or -1
};

class NgcInterpreter {
 public:
  /// `startMm`: machine position at the start of the program, when known.
  NgcInterpreter(const WorkOffsets& offsets, const ToolTable& tools, std::optional<Vec3> startMm,
                 Decimals decimals);

  /// Interprets one tokenized line. Returns false and sets `error` when the line is rejected.
  bool execute(const Block& block, NgcLine& out, LineError& error);

  const Position& position() const noexcept { return position_; }
  bool ended() const noexcept { return ended_; }
  PrintMode printMode() const noexcept;

 private:
  struct LineWords;
  Frame frame() const noexcept;
  /// The steps of execute(), in LinuxCNC's order; each returns false with `error` set when the
  /// line is rejected.
  bool sortWords(LineWords& words, NgcLine& out, LineError& error) const;
  bool applyFeedAndTools(const LineWords& words, LineError& error);
  bool applyToolLength(const LineWords& words, bool& axisWordsUsed, LineError& error);
  bool applyCoordinateSystem(const LineWords& words, LineError& error);
  bool executeMotion(const LineWords& words, bool axisWordsUsed, NgcLine& out, LineError& error);
  /// Rejects a move without a motion mode, G53 with an arc or G91, a feed move without a feed.
  bool checkMotion(const LineWords& words, LineError& error) const;
  /// The end of the move (machine mm) from the axis words; `known` gains the axes they set.
  void moveEnd(const LineWords& words, const Vec3& startProgram, Vec3& endMm, std::uint8_t& known,
               NgcLine& out) const;
  /// Checks the arc words of a G2/G3 line and, when the start is known, sets `out.move.arc`.
  bool arcMove(const LineWords& words, const Vec3& startProgram, NgcLine& out,
               LineError& error) const;

  WorkOffsets offsets_;
  ToolTable tools_;
  Decimals decimals_;
  Position position_;
  LengthUnit units_ = LengthUnit::Mm;
  bool incremental_ = false;
  bool arcIncremental_ = true;
  int plane_ = 0;
  int motion_ = -1;  // 0..3, -1 none (G80 or nothing yet)
  int system_ = 0;
  Vec3 toolOffsetMm_ = Vec3::Zero();
  int selectedTool_ = -1;
  int toolInSpindle_ = 0;
  double feed_ = 0.0;
  bool ended_ = false;
};

}  // namespace volcomp::nc
