// The one reader of positioning-run CSV files. Kept self-contained (splitting, numbers, units) so
// that it can move onto the project's shared measurement-CSV reader without touching its callers.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <optional>
#include <set>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"
#include "volcomp/config/text_input.hpp"
#include "volcomp/metrology/positioning_runs.hpp"

namespace volcomp::metrology {
namespace {

using config::ConfigError;
using config::quoted;

// An ISO 230-2 test has a few hundred readings; a file with more rows than this is not one, and
// is refused while it is read, before the memory is spent.
constexpr std::size_t kMaxReadings = 1000000;

std::string trim(std::string_view text) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && isSpace(text.back())) text.remove_suffix(1);
  // A UTF-8 byte-order mark, which spreadsheet exports put before the first header.
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return std::string(text);
}

std::vector<std::string> split(const std::string& line, char delimiter) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t at = line.find(delimiter, start);
    if (at == std::string::npos) {
      fields.push_back(trim(std::string_view(line).substr(start)));
      return fields;
    }
    fields.push_back(trim(std::string_view(line).substr(start, at - start)));
    start = at + 1;
  }
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

/// Length unit name -> factor to mm; nullopt when not a unit.
std::optional<double> unitToMm(const std::string& unit) {
  if (unit == "mm") return 1.0;
  if (unit == "um" || unit == "\xC2\xB5m" || unit == "\xCE\xBCm" || unit == "micron" ||
      unit == "microns") {
    return 1e-3;
  }
  if (unit == "nm") return 1e-6;
  if (unit == "m") return 1e3;
  if (unit == "in" || unit == "inch") return 25.4;
  return std::nullopt;
}

struct HeaderName {
  std::string name;  // lower case, spaces and hyphens as '_'
  std::string unit;  // as written (lower case), empty when none
};

/// "Target [mm]", "target (mm)", "target_mm", "Deviation um" -> {name, unit}.
HeaderName splitHeader(const std::string& field) {
  std::string text = lower(field);
  HeaderName out;
  const char close = text.empty() ? '\0' : text.back();
  if (close == ']' || close == ')') {
    const std::size_t open = text.rfind(close == ']' ? '[' : '(');
    if (open != std::string::npos) {
      out.unit = trim(std::string_view(text).substr(open + 1, text.size() - open - 2));
      text = trim(std::string_view(text).substr(0, open));
    }
  } else {
    const std::size_t cut = text.find_last_of("_ /");
    if (cut != std::string::npos && unitToMm(trim(text.substr(cut + 1)))) {
      out.unit = trim(text.substr(cut + 1));
      text = trim(std::string_view(text).substr(0, cut));
    }
  }
  for (char& c : text) {
    if (c == ' ' || c == '-') c = '_';
  }
  while (!text.empty() && (text.back() == '_' || text.back() == '/')) text.pop_back();
  out.name = text;
  return out;
}

enum class Column { Target, Deviation, Actual, Run, Direction, Axis, Unknown };

Column classify(const std::string& name) {
  static const std::vector<std::pair<Column, std::vector<std::string>>> aliases{
      {Column::Target, {"target", "target_position", "nominal", "nominal_position", "position"}},
      {Column::Deviation, {"deviation", "positional_deviation", "error", "position_error"}},
      {Column::Actual, {"actual", "actual_position", "measured", "measured_position"}},
      {Column::Run, {"run", "run_number", "run_no", "cycle"}},
      {Column::Direction, {"direction", "dir", "approach"}},
      {Column::Axis, {"axis"}},
  };
  for (const auto& [column, names] : aliases) {
    if (std::find(names.begin(), names.end(), name) != names.end()) return column;
  }
  return Column::Unknown;
}

std::string where(int line, const std::string& column) {
  return "line " + std::to_string(line) +
         (column.empty() ? "" : ", column " + config::printable(column, config::kQuotedBytes));
}

double parseNumber(std::string text, bool decimalComma, const std::string& file, int line,
                   const std::string& column) {
  if (decimalComma) std::replace(text.begin(), text.end(), ',', '.');
  double value = 0.0;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;
  const auto [pointer, error] = std::from_chars(begin, end, value);
  if (text.empty() || error != std::errc() || pointer != end || !std::isfinite(value)) {
    throw ConfigError(file, where(line, column), "expected a finite number, got " + quoted(text));
  }
  return value;
}

model::Direction parseDirection(const std::string& text, const std::string& file, int line,
                                const std::string& column) {
  const std::string value = lower(text);
  static const std::vector<std::string> up{"+",   "+1",      "1",   "up",       "u",           "fw",
                                           "fwd", "forward", "pos", "positive", "\xE2\x86\x91"};
  static const std::vector<std::string> down{"-",        "-1",  "down",     "d",
                                             "bw",       "bwd", "rev",      "reverse",
                                             "backward", "neg", "negative", "\xE2\x86\x93"};
  if (std::find(up.begin(), up.end(), value) != up.end()) return model::Direction::Positive;
  if (std::find(down.begin(), down.end(), value) != down.end()) return model::Direction::Negative;
  throw ConfigError(file, where(line, column),
                    "expected the approach direction (+, up, forward or \xE2\x86\x91; -, down, "
                    "reverse or \xE2\x86\x93), got " +
                        quoted(text));
}

std::string normaliseAxis(const std::string& text) {
  std::string axis = trim(text);
  for (char& c : axis) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return axis;
}

struct Layout {
  char delimiter = ',';
  bool decimalComma = false;
  std::optional<std::size_t> target, deviation, actual, run, direction, axis;
  double targetToMm = 1.0, deviationToMm = 1.0, actualToMm = 1.0;
  std::vector<std::string> names;  // header fields as written
};

Layout readHeader(const std::string& line, const std::string& file, int lineNumber,
                  std::vector<std::string>& ignored) {
  Layout layout;
  if (line.find(';') != std::string::npos && line.find(',') == std::string::npos) {
    layout.delimiter = ';';
    layout.decimalComma = true;
  }
  layout.names = split(line, layout.delimiter);
  for (std::size_t i = 0; i < layout.names.size(); ++i) {
    const HeaderName header = splitHeader(layout.names[i]);
    const Column column = classify(header.name);
    const auto lengthColumn = [&](std::optional<std::size_t>& slot, double& factor,
                                  const char* example) {
      if (slot) {
        throw ConfigError(file, where(lineNumber, layout.names[i]),
                          "column " + quoted(header.name) + " appears twice");
      }
      if (header.unit.empty()) {
        throw ConfigError(file, where(lineNumber, layout.names[i]),
                          "a length column needs its unit in the header, e.g. \"" +
                              std::string(example) + "\" (units: nm, um, mm, m, in)");
      }
      const std::optional<double> toMm = unitToMm(header.unit);
      if (!toMm) {
        throw ConfigError(file, where(lineNumber, layout.names[i]),
                          "unknown length unit " + quoted(header.unit) +
                              " (expected nm, um, \xC2\xB5m, mm, m or in)");
      }
      slot = i;
      factor = *toMm;
    };
    const auto plainColumn = [&](std::optional<std::size_t>& slot) {
      if (slot) {
        throw ConfigError(file, where(lineNumber, layout.names[i]),
                          "column " + quoted(header.name) + " appears twice");
      }
      slot = i;
    };
    switch (column) {
      case Column::Target:
        lengthColumn(layout.target, layout.targetToMm, "target_mm");
        break;
      case Column::Deviation:
        lengthColumn(layout.deviation, layout.deviationToMm, "deviation_um");
        break;
      case Column::Actual:
        lengthColumn(layout.actual, layout.actualToMm, "actual_mm");
        break;
      case Column::Run:
        plainColumn(layout.run);
        break;
      case Column::Direction:
        plainColumn(layout.direction);
        break;
      case Column::Axis:
        plainColumn(layout.axis);
        break;
      case Column::Unknown:
        if (!layout.names[i].empty()) ignored.push_back(layout.names[i]);
        break;
    }
  }
  const auto require = [&](bool present, const std::string& what) {
    if (!present) {
      throw ConfigError(file, where(lineNumber, ""),
                        "the header has no " + what +
                            " column (expected target_<unit>, deviation_<unit> or "
                            "actual_<unit>, run, direction; see docs/iso230-2.md)");
    }
  };
  require(layout.target.has_value(), "target position (target_mm)");
  require(layout.deviation || layout.actual, "deviation (deviation_um) or actual position");
  require(layout.run.has_value(), "run");
  require(layout.direction.has_value(), "direction");
  if (layout.deviation && layout.actual) {
    throw ConfigError(file, where(lineNumber, ""),
                      "give either a deviation column or an actual-position column, not both");
  }
  return layout;
}

}  // namespace

PositioningRuns parsePositioningCsv(std::istream& input, const std::string& file,
                                    const std::string& axisFilter) {
  PositioningRuns runs;
  runs.file = file;
  const std::string wantedAxis = normaliseAxis(axisFilter);
  std::optional<Layout> layout;
  std::set<std::string> axesSeen;
  config::LineReader lines(input, file);
  std::string_view line;
  int lineNumber = 0;
  while (lines.next(line)) {
    lineNumber = static_cast<int>(lines.lineNumber());
    const std::string text = trim(line);
    if (text.empty() || text.front() == '#') continue;
    if (!layout) {
      layout = readHeader(text, file, lineNumber, runs.ignoredColumns);
      continue;
    }
    const std::vector<std::string> fields = split(text, layout->delimiter);
    if (fields.size() < layout->names.size()) {
      throw ConfigError(file, where(lineNumber, ""),
                        "expected " + std::to_string(layout->names.size()) + " fields, got " +
                            std::to_string(fields.size()));
    }
    const auto field = [&](std::size_t index) -> const std::string& { return fields[index]; };
    const auto name = [&](std::size_t index) -> const std::string& { return layout->names[index]; };
    if (layout->axis) {
      const std::string axis = normaliseAxis(field(*layout->axis));
      if (axis != "X" && axis != "Y" && axis != "Z") {
        throw ConfigError(file, where(lineNumber, name(*layout->axis)),
                          "expected the axis X, Y or Z, got " + quoted(field(*layout->axis)));
      }
      if (!wantedAxis.empty() && axis != wantedAxis) continue;
      axesSeen.insert(axis);
    }
    PositioningSample sample;
    sample.line = lineNumber;
    sample.targetMm = parseNumber(field(*layout->target), layout->decimalComma, file, lineNumber,
                                  name(*layout->target)) *
                      layout->targetToMm;
    if (layout->deviation) {
      sample.deviationMm = parseNumber(field(*layout->deviation), layout->decimalComma, file,
                                       lineNumber, name(*layout->deviation)) *
                           layout->deviationToMm;
    } else {
      const double actualMm = parseNumber(field(*layout->actual), layout->decimalComma, file,
                                          lineNumber, name(*layout->actual)) *
                              layout->actualToMm;
      sample.deviationMm = actualMm - sample.targetMm;
    }
    const double run = parseNumber(field(*layout->run), layout->decimalComma, file, lineNumber,
                                   name(*layout->run));
    if (run != std::floor(run) || run < 0 || run > 1e6) {
      throw ConfigError(
          file, where(lineNumber, name(*layout->run)),
          "expected a run number (a whole number >= 0), got " + quoted(field(*layout->run)));
    }
    sample.run = static_cast<int>(run);
    sample.direction =
        parseDirection(field(*layout->direction), file, lineNumber, name(*layout->direction));
    if (runs.samples.size() == kMaxReadings) {
      throw ConfigError(file, where(lineNumber, ""),
                        "more than " + std::to_string(kMaxReadings) +
                            " readings: not the data of one positioning test");
    }
    runs.samples.push_back(sample);
  }
  if (!layout) throw ConfigError(file, "", "no header line (the file is empty)");
  if (axesSeen.size() > 1) {
    std::string list;
    for (const std::string& axis : axesSeen) list += (list.empty() ? "" : ", ") + axis;
    throw ConfigError(file, "column axis",
                      "the file holds several axes (" + list + "): choose one with --axis");
  }
  runs.axis = !wantedAxis.empty() ? wantedAxis : (axesSeen.empty() ? "" : *axesSeen.begin());
  if (runs.samples.empty()) {
    throw ConfigError(
        file, "",
        wantedAxis.empty() ? "no readings after the header" : "no readings of axis " + wantedAxis);
  }
  return runs;
}

PositioningRuns readPositioningCsv(const std::string& path, const std::string& axisFilter) {
  std::ifstream input = config::openTextFile(path);
  return parsePositioningCsv(input, path, axisFilter);
}

}  // namespace volcomp::metrology
