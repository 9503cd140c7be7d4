#include "volcomp/nc/nc_error.hpp"

#include <utility>

namespace volcomp::nc {
namespace {

std::string where(const std::string& file, long line, int column) {
  std::string text = file;
  if (line > 0) text += ":" + std::to_string(line);
  if (line > 0 && column > 0) text += ":" + std::to_string(column);
  return text;
}

}  // namespace

NcError::NcError(std::string file, long line, int column, std::string message)
    : std::runtime_error(where(file, line, column) + ": " + message),
      file_(std::move(file)),
      line_(line),
      column_(column),
      message_(std::move(message)) {}

}  // namespace volcomp::nc
