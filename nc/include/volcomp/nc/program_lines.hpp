#pragma once
/// The interface between the readers of programs (RS274/NGC, LinuxCNC canonical commands) and the
/// compensation: a chunk of lines, each to be copied, replaced by generated text, dropped, or
/// written as a compensated motion from a template.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "volcomp/nc/interpreter_state.hpp"
#include "volcomp/nc/move.hpp"

namespace volcomp::nc {

/// A piece of a chunk's text arena.
struct TextRef {
  std::uint32_t begin = 0;
  std::uint32_t size = 0;
};

struct MotionWork {
  Move move;
  long line = 0;
  bool startKnown = false;  ///< the start position is known: the move can be compensated
  bool endKnown = false;    ///< the end position is known (else the line is copied unchanged)
  PrintMode before;         ///< for a reversal line written before this line
  PrintMode after;          ///< for the line's own coordinates
  TextRef prefix;           ///< first written line = prefix + motion + suffix
  TextRef suffix;
  TextRef tail;  ///< written on its own line after the last piece ("" = none)
  TextRef feed;  ///< the line's F word, repeated on a reversal line ("" = none)
};

enum class LineAction : std::uint8_t {
  Copy,    ///< write the input line unchanged
  Text,    ///< write `text` instead (may be several lines joined by '\n')
  Drop,    ///< write nothing
  Motion,  ///< write the compensated motion `motion`
};

struct LineWork {
  LineAction action = LineAction::Copy;
  std::string_view input;  ///< the input line without its line ending
  std::string_view eol;    ///< its line ending ("\n", "\r\n" or "")
  TextRef text;
  std::uint32_t motion = 0;
};

/// The lines of one chunk and the text they refer to.
struct Chunk {
  std::vector<LineWork> lines;
  std::vector<MotionWork> motions;
  std::string arena;

  void clear() {
    lines.clear();
    motions.clear();
    arena.clear();
  }
  TextRef store(std::string_view text) {
    TextRef r{static_cast<std::uint32_t>(arena.size()), static_cast<std::uint32_t>(text.size())};
    arena.append(text);
    return r;
  }
  std::string_view view(TextRef r) const { return std::string_view(arena).substr(r.begin, r.size); }
};

/// Reads one kind of program. read() interprets one line and appends what to do with it to the
/// chunk; it throws NcError (file:line:column) when the line is rejected.
class ProgramReader {
 public:
  virtual ~ProgramReader() = default;
  virtual const char* formatName() const noexcept = 0;
  /// The program's file name, for messages.
  virtual const std::string& file() const noexcept = 0;
  /// Text written before the first line (with its line endings).
  virtual void header(std::string& /*out*/) {}
  virtual void read(std::string_view line, std::string_view eol, long number, Chunk& chunk) = 0;
  /// Text written after the last line.
  virtual void trailer(std::string& /*out*/) {}
};

}  // namespace volcomp::nc
