#include "points_csv.hpp"

#include <string_view>
#include <vector>

#include "cli_support.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"

namespace volcomp::cli {
namespace {

std::string lineKey(std::size_t line) {
  return "line " + std::to_string(line);
}

bool isHeader(std::string_view line) {
  if (line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM from spreadsheets
  const std::vector<std::string_view> fields = splitFields(line);
  if (fields.size() != 3) return false;
  const char* names[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    if (fields[i].size() != 1 || (fields[i][0] | 0x20) != names[i][0]) return false;
  }
  return true;
}

}  // namespace

PointsCsvReader::PointsCsvReader(std::istream& in, const std::string& file)
    : lines_(in, file), file_(file) {
  std::string_view line;
  while (lines_.next(line)) {
    if (trim(line).empty()) continue;
    if (!isHeader(line)) {
      throw config::ConfigError(file_, lineKey(lines_.lineNumber()),
                                "expected the header x,y,z, got " + config::quoted(trim(line)));
    }
    return;
  }
  throw config::ConfigError(file_, "", "expected the header x,y,z, got an empty file");
}

bool PointsCsvReader::next(Eigen::Vector3d& qMm) {
  std::string_view line;
  while (lines_.next(line)) {
    if (trim(line).empty()) continue;
    const std::vector<std::string_view> fields = splitFields(line);
    double q[3] = {0, 0, 0};
    bool ok = fields.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) ok = parseDouble(fields[i], q[i]);
    if (!ok) {
      throw config::ConfigError(
          file_, lineKey(lines_.lineNumber()),
          "expected three finite numbers x,y,z (mm), got " + config::quoted(trim(line)));
    }
    qMm = Eigen::Vector3d(q[0], q[1], q[2]);
    return true;
  }
  return false;
}

}  // namespace volcomp::cli
