#pragma once
/// A rejected NC program line: where (file:line:column, 1-based) and what was found or expected.
/// Thrown by the readers of RS274/NGC programs and of LinuxCNC canonical commands, and by the
/// work-offset and tool-table readers; caught at the edge (the CLI prints what() on one line).

#include <stdexcept>
#include <string>

namespace volcomp::nc {

class NcError : public std::runtime_error {
 public:
  /// what() reads "FILE:LINE:COLUMN: MESSAGE" (":COLUMN" left out when column is 0, ":LINE" when
  /// line is 0), with control characters and invalid UTF-8 escaped (config::printable): a tab
  /// inside a quoted word shows as \t.
  NcError(std::string file, long line, int column, std::string message);

  const std::string& file() const noexcept { return file_; }
  long line() const noexcept { return line_; }
  int column() const noexcept { return column_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::string file_;
  long line_;
  int column_;
  std::string message_;
};

/// An error found inside one line before the caller knows the file and line number: a column
/// (1-based) and a message. Readers turn it into an NcError.
struct LineError {
  int column = 0;
  std::string message;
};

}  // namespace volcomp::nc
