#pragma once
/// Output formatting of the compensator: the lines of the compensated program,
/// with the motion of a moving line replaced by its pieces (and the reversal
/// and lead-in moves before them).

#include <string>
#include <string_view>
#include <vector>

#include "printed_path.hpp"
#include "volcomp/nc/program_lines.hpp"
#include "volcomp/nc/report.hpp"

namespace volcomp::nc::detail {

class MotionWriter {
 public:
  /// Counts the lines written into `report` (linesOut, motionLinesOut).
  explicit MotionWriter(NcReport& report) : report_(report) {}

  /// Appends one line of text (which may hold several lines joined by '\n').
  void line(std::string_view text, std::string_view eol);
  /// Appends the lines of a moving line: its pieces, in order, written in the
  /// line's own text.
  void writeMotion(const LineWork& lw, const MotionWork& w, const std::vector<Piece>& pieces,
                   const Chunk& chunk);

  /// What is written so far and not yet handed to the sink.
  std::string out;

 private:
  NcReport& report_;
};

}  // namespace volcomp::nc::detail
