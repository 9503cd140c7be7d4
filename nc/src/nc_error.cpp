#include "volcomp/nc/nc_error.hpp"

#include <utility>

#include "volcomp/config/printable.hpp"

namespace volcomp::nc {
namespace {

std::string where(const std::string& file, long line, int column) {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  if (line > 0 && column > 0) text += ":" + std::to_string(column);
  return text;
}

}  // namespace

// Messages quote the program's text (a word, a name), which can hold tabs, control characters or
// invalid UTF-8: what() is shown on a terminal, so all of it goes through printable().
NcError::NcError(std::string file, long line, int column, std::string message)
    : std::runtime_error(config::printable(where(file, line, column) + ": " + message)),
      file_(std::move(file)),
      line_(line),
      column_(column),
      message_(config::printable(message)) {}

}  // namespace volcomp::nc
