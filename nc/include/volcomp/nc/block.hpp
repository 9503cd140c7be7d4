#pragma once
/// One RS274/NGC line split into words (a letter and a number) and comments, with the column of
/// every word, without allocation. Only the syntax is checked here (what LinuxCNC would read as
/// words); what the words mean is the interpreter's business (ngc_interpreter.hpp).

#include <array>
#include <cstdint>
#include <string_view>

#include "volcomp/nc/nc_error.hpp"

namespace volcomp::nc {

struct Word {
  char letter = 0;          ///< upper case
  double value = 0.0;       ///< the number as written (program units for coordinates)
  std::uint32_t begin = 0;  ///< offset of the letter in the line
  std::uint32_t end = 0;    ///< one past the last character of the number
};

inline constexpr int kMaxWords = 48;

struct Block {
  std::string_view text;  ///< the line, without its line ending
  std::array<Word, kMaxWords> words{};
  int wordCount = 0;
  bool percent = false;  ///< the line is a '%' program delimiter
  bool comment = false;  ///< the line holds a comment ("(...)" or ";...")
};

/// Splits `line` into words and comments. Rejected, with the column and what was found: parameters
/// and expressions ('#', '['), O-words, block delete ('/'), polar coordinates ('@', '^'), unclosed
/// or nested comments, a letter without a number, any other character, more than kMaxWords words.
/// Returns false and sets `error` when rejected.
bool tokenize(std::string_view line, Block& block, LineError& error);

}  // namespace volcomp::nc
