#include "motion_writer.hpp"

#include <algorithm>

#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc::detail {
namespace {

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

}  // namespace

void MotionWriter::line(std::string_view text, std::string_view eol) {
  out.append(text);
  out.append(eol.empty() ? std::string_view("\n") : eol);
  report_.linesOut += 1 + static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

void MotionWriter::writeMotion(const LineWork& lw, const MotionWork& w,
                               const std::vector<Piece>& pieces, const Chunk& chunk) {
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
  ++report_.motionLinesOut;
  for (++i; i < pieces.size(); ++i) {
    text.clear();
    appendMotion(text, pieces[i], rapid);
    if (pieces[i].kind == PieceKind::Reversal) text += " (volcomp: reversal)";
    line(text, lw.eol);
    if (pieces[i].kind == PieceKind::Normal) ++report_.motionLinesOut;
  }
  if (w.tail.size > 0) line(chunk.view(w.tail), lw.eol);
}

}  // namespace volcomp::nc::detail
