#pragma once
/// The RS274/NGC reader of the compensation: tokenizes each line, interprets it (ngc_interpreter),
/// and keeps everything but the coordinates of moves: comments, N numbers, F/S/T/M words, modal
/// words and the line structure. A moving line becomes
///   [reversal line]  prefix + "G1 X.. Y.. Z.." + suffix  [more pieces]  [stop codes]
/// where the axis words, arc words (I J K R P), the motion code and G53 are replaced by the
/// written motion, and stop codes (M0 M1 M2 M30 M60) move after the last piece, so that they
/// still run after the whole move.

#include <optional>
#include <string>

#include "volcomp/nc/ngc_interpreter.hpp"
#include "volcomp/nc/program_lines.hpp"

namespace volcomp::nc {

class NgcReader final : public ProgramReader {
 public:
  NgcReader(std::string file, const WorkOffsets& offsets, const ToolTable& tools,
            std::optional<Vec3> startMm, Decimals decimals);
  const char* formatName() const noexcept override { return "ngc"; }
  const std::string& file() const noexcept override { return file_; }
  void read(std::string_view line, std::string_view eol, long number, Chunk& chunk) override;

 private:
  std::string file_;
  NgcInterpreter interpreter_;
  Block block_;
  NgcLine result_;
  LineError error_;
};

}  // namespace volcomp::nc
