#pragma once
/// Reading input files for the parsers, with bounds: whatever a file holds, a parser gets either
/// its text or a ConfigError that says what is wrong with the file itself, never a crash, an
/// out-of-memory kill or a misleading "invalid JSON".
///
/// - readTextFile: a whole file (JSON, DBC), at most maxBytes.
/// - openTextFile: a stream for line-by-line reading (CSV files of any length).
/// - LineReader: the lines of a stream, each at most maxLineBytes, numbered from 1.
/// Errors name the file: "cannot open file: No such file or directory", "is a directory, not a
/// file", "larger than 64 MiB", "line 3: longer than 1 MiB: ...", "cannot read: Input/output
/// error".

#include <cstddef>
#include <fstream>
#include <istream>
#include <string>
#include <string_view>

namespace volcomp::config {

/// Largest file readTextFile takes by default (model files with large grids stay far below).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{64} << 20;
/// Longest line a LineReader takes by default (a CSV row of a few dozen numbers is < 1 kB).
inline constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

/// The whole content of `path`. Throws ConfigError(path, "", why) when it cannot be opened or
/// read, is a directory or is larger than `maxBytes`.
std::string readTextFile(const std::string& path, std::size_t maxBytes = kMaxTextFileBytes);

/// `path` opened for reading (binary: lines keep a '\r', which LineReader drops). Throws
/// ConfigError(path, "", why) when it cannot be opened or is a directory.
std::ifstream openTextFile(const std::string& path);

/// The lines of a text stream, without their '\n' and a '\r' before it.
class LineReader {
 public:
  /// `file` names the input in messages.
  LineReader(std::istream& in, std::string file, std::size_t maxLineBytes = kMaxLineBytes);

  /// Reads the next line into `line` (valid until the next call); false at the end of the input.
  /// Throws ConfigError(file, "line N", ...) for a line longer than the limit and for a read
  /// error.
  bool next(std::string_view& line);
  /// Number of the line last returned (1-based; 0 before the first).
  std::size_t lineNumber() const noexcept { return lineNumber_; }
  const std::string& file() const noexcept { return file_; }

 private:
  std::istream& in_;
  std::string file_;
  std::size_t maxLineBytes_;
  std::string buffer_;
  std::size_t lineNumber_ = 0;
};

}  // namespace volcomp::config
