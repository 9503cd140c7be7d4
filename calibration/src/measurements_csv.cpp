#include "volcomp/calibration/measurements.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"
#include "volcomp/config/text_input.hpp"

namespace volcomp::calibration {
namespace {

using config::ConfigError;
using config::quoted;

// A calibration with more points than this needs a Jacobian of several GB; a file with more rows
// is refused while it is read, before the memory is spent.
constexpr std::size_t kMaxMeasurements = 1000000;

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(line);
  while (std::getline(stream, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string linePath(int line) {
  return "line " + std::to_string(line);
}

bool isKnownColumn(const std::string& name) {
  // ox,oy,oz (compensation offsets in `volcomp eval --points` output) are accepted and ignored,
  // so that eval's output can be fed back for round trips.
  static const std::vector<std::string> known{"x",  "y",  "z",  "ex", "ey", "ez", "tx", "ty",
                                              "tz", "ea", "eb", "ec", "ox", "oy", "oz", "weight"};
  for (const std::string& k : known) {
    if (k == name) return true;
  }
  if (name.size() == 2 && name[0] == 'q' && name[1] >= '1' && name[1] <= '9') return true;
  return false;
}

double parseNumber(const std::string& text, const std::string& file, int line,
                   const std::string& column) {
  double value = 0.0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (!text.empty() && *begin == '+') ++begin;
  const auto [pointer, error] = std::from_chars(begin, end, value);
  if (text.empty() || error != std::errc() || pointer != end || !std::isfinite(value)) {
    throw ConfigError(file, linePath(line) + ", column " + column,
                      "expected a finite number, got " + quoted(text));
  }
  return value;
}

}  // namespace

MeasurementSet parseMeasurementsCsv(std::istream& input, const std::string& file) {
  MeasurementSet set;
  set.file = file;
  config::LineReader lines(input, file);
  std::string_view text;
  int lineNumber = 0;
  std::vector<std::string> header;
  std::map<std::string, std::size_t> column;
  while (lines.next(text)) {
    lineNumber = static_cast<int>(lines.lineNumber());
    const std::string line = trim(std::string(text));
    if (line.empty() || line[0] == '#') continue;
    if (header.empty()) {
      header = splitFields(line);
      for (std::size_t c = 0; c < header.size(); ++c) {
        const std::string& name = header[c];
        if (!isKnownColumn(name)) {
          throw ConfigError(file, linePath(lineNumber),
                            "unknown column " + quoted(name) +
                                " (expected x,y,z,ex,ey,ez and optionally tx,ty,tz, ea,eb,ec, "
                                "weight, q1..q9; ox,oy,oz are ignored)");
        }
        if (!column.emplace(name, c).second) {
          throw ConfigError(file, linePath(lineNumber),
                            "column " + quoted(name) + " appears twice");
        }
      }
      for (const char* required : {"x", "y", "z", "ex", "ey", "ez"}) {
        if (!column.count(required)) {
          throw ConfigError(file, linePath(lineNumber),
                            std::string("missing column \"") + required +
                                "\" (the header needs at least x,y,z,ex,ey,ez)");
        }
      }
      const auto groupCount = [&](std::initializer_list<const char*> names) {
        int count = 0;
        for (const char* name : names) count += column.count(name) ? 1 : 0;
        return count;
      };
      const int tool = groupCount({"tx", "ty", "tz"});
      const int angles = groupCount({"ea", "eb", "ec"});
      if (tool != 0 && tool != 3) {
        throw ConfigError(file, linePath(lineNumber), "give all of tx,ty,tz or none");
      }
      if (angles != 0 && angles != 3) {
        throw ConfigError(file, linePath(lineNumber), "give all of ea,eb,ec or none");
      }
      set.hasTool = tool == 3;
      set.hasAngles = angles == 3;
      for (int j = 1; j <= 9; ++j) {
        if (column.count("q" + std::to_string(j))) {
          if (j != set.jointColumns + 1) {
            throw ConfigError(file, linePath(lineNumber),
                              "joint columns must be q1..qN without gaps");
          }
          set.jointColumns = j;
        }
      }
      continue;
    }
    const std::vector<std::string> fields = splitFields(line);
    if (fields.size() != header.size()) {
      throw ConfigError(file, linePath(lineNumber),
                        "expected " + std::to_string(header.size()) +
                            " fields as in the header, got " + std::to_string(fields.size()));
    }
    const auto value = [&](const std::string& name) {
      return parseNumber(fields[column.at(name)], file, lineNumber, name);
    };
    Measurement m;
    m.line = lineNumber;
    m.qMm = {value("x"), value("y"), value("z")};
    m.errorMm = {value("ex"), value("ey"), value("ez")};
    if (set.hasTool) m.toolMm = {value("tx"), value("ty"), value("tz")};
    if (set.hasAngles) m.angularErrorRad = {value("ea"), value("eb"), value("ec")};
    for (int j = 1; j <= set.jointColumns; ++j) m.joints.push_back(value("q" + std::to_string(j)));
    if (column.count("weight")) {
      m.weight = value("weight");
      if (!(m.weight > 0.0)) {
        throw ConfigError(file, linePath(lineNumber) + ", column weight",
                          "expected a weight > 0, got " + quoted(fields[column.at("weight")]));
      }
    }
    if (set.points.size() == kMaxMeasurements) {
      throw ConfigError(file, linePath(lineNumber),
                        "more than " + std::to_string(kMaxMeasurements) +
                            " measurements: thin the data out before calibrating");
    }
    set.points.push_back(std::move(m));
  }
  if (header.empty())
    throw ConfigError(file, "", "empty file: expected a header line x,y,z,ex,ey,ez");
  if (set.points.empty()) throw ConfigError(file, "", "no measurement rows after the header");
  return set;
}

MeasurementSet readMeasurementsCsv(const std::string& path) {
  std::ifstream input = config::openTextFile(path);
  return parseMeasurementsCsv(input, path);
}

}  // namespace volcomp::calibration
