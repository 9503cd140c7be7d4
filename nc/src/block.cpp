#include "volcomp/nc/block.hpp"

#include <string>

#include "volcomp/nc/numbers.hpp"

namespace volcomp::nc {
namespace {

bool isBlank(char c) noexcept {
  return c == ' ' || c == '\t' || c == '\r';
}

bool fail(LineError& error, std::size_t offset, std::string message) {
  error.column = static_cast<int>(offset) + 1;
  error.message = std::move(message);
  return false;
}

std::string quoted(char c) {
  if (c >= 32 && c < 127) return std::string("'") + c + "'";
  return "byte " + std::to_string(static_cast<unsigned char>(c));
}

}  // namespace

bool tokenize(std::string_view line, Block& block, LineError& error) {
  block.text = line;
  block.wordCount = 0;
  block.percent = false;
  block.comment = false;
  std::size_t i = 0;
  while (i < line.size() && isBlank(line[i])) ++i;
  if (i < line.size() && line[i] == '%') {
    std::size_t j = i + 1;
    while (j < line.size() && isBlank(line[j])) ++j;
    if (j == line.size()) {
      block.percent = true;
      return true;
    }
  }
  if (i < line.size() && line[i] == '/') {
    return fail(error, i,
                "block delete ('/') is not supported: whether the line runs depends on a switch "
                "at the controller");
  }
  while (i < line.size()) {
    const char c = line[i];
    if (isBlank(c)) {
      ++i;
      continue;
    }
    if (c == '(') {
      const std::size_t close = line.find(')', i + 1);
      const std::size_t nested = line.find('(', i + 1);
      if (close == std::string_view::npos) return fail(error, i, "comment without closing ')'");
      if (nested < close) return fail(error, nested, "nested comment: '(' inside a comment");
      block.comment = true;
      i = close + 1;
      continue;
    }
    if (c == ';') {
      block.comment = true;
      break;
    }
    if (c == '#') {
      return fail(error, i,
                  "parameters ('#') are not supported; flatten the program with rs274 -g");
    }
    if (c == '[') {
      return fail(error, i,
                  "expressions ('[') are not supported; flatten the program with rs274 -g");
    }
    if (c == '@' || c == '^') {
      return fail(error, i, std::string("polar coordinates (") + quoted(c) + ") are not supported");
    }
    const char letter = (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
    if (letter < 'A' || letter > 'Z') return fail(error, i, "unexpected character " + quoted(c));
    if (letter == 'O') {
      return fail(error, i,
                  "O-words (subroutines, loops, conditions) are not supported; flatten the "
                  "program with rs274 -g");
    }
    std::size_t pos = i + 1;
    double value = 0.0;
    if (!scanNumber(line, pos, value)) {
      std::size_t next = i + 1;
      while (next < line.size() && isBlank(line[next])) ++next;
      if (next < line.size() && (line[next] == '#' || line[next] == '[')) {
        return fail(error, next,
                    std::string("parameters and expressions after ") + letter +
                        " are not supported; flatten the program with rs274 -g");
      }
      return fail(error, i, std::string("expected a number after ") + letter);
    }
    if (block.wordCount == kMaxWords) {
      return fail(error, i, "more than " + std::to_string(kMaxWords) + " words on one line");
    }
    Word& w = block.words[static_cast<std::size_t>(block.wordCount++)];
    w.letter = letter;
    w.value = value;
    w.begin = static_cast<std::uint32_t>(i);
    w.end = static_cast<std::uint32_t>(pos);
    i = pos;
  }
  return true;
}

}  // namespace volcomp::nc
