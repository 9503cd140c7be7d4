// The positioning-run CSV (docs/iso230-2.md) read through config::CsvReader, which gives it the
// delimiter, decimal comma, header units and aliases of laser-software exports. What is decided
// here: which columns make a run file, and how a direction or an axis is spelt.

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <istream>
#include <optional>
#include <set>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/printable.hpp"
#include "volcomp/metrology/axis_tables.hpp"
#include "volcomp/metrology/positioning_runs.hpp"

namespace volcomp::metrology {
namespace {

using config::ConfigError;
using config::CsvQuantity;
using config::quoted;

// An ISO 230-2 test has a few hundred readings; a file with more rows than this is not one, and
// is refused while it is read, before the memory is spent.
constexpr std::size_t kMaxReadings = 1000000;

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

config::CsvSchema runsSchema() {
  config::CsvSchema schema;
  schema.add({"target", "deviation", "actual"}, CsvQuantity::Length)
      .add({"run"}, CsvQuantity::Number)
      .add({"direction", "axis"}, CsvQuantity::Text)
      .alias("target", {"target_position", "nominal", "nominal_position", "position"})
      .alias("deviation", {"positional_deviation", "error", "position_error"})
      .alias("actual", {"actual_position", "measured", "measured_position"})
      .alias("run", {"run_number", "run_no", "cycle"})
      .alias("direction", {"dir", "approach"});
  // Instrument files: a length without its unit is refused rather than guessed; the exports
  // carry columns of their own (temperatures, time stamps), which are listed, not refused.
  schema.lengthUnitRequired = true;
  schema.acceptOtherColumns = true;
  return schema;
}

model::Direction parseDirection(const config::CsvReader& csv, int column) {
  const std::string value = lower(std::string(csv.field(column)));
  static const std::vector<std::string> up{"+",   "+1",      "1",   "up",       "u",           "fw",
                                           "fwd", "forward", "pos", "positive", "\xE2\x86\x91"};
  static const std::vector<std::string> down{"-",        "-1",  "down",     "d",
                                             "bw",       "bwd", "rev",      "reverse",
                                             "backward", "neg", "negative", "\xE2\x86\x93"};
  if (std::find(up.begin(), up.end(), value) != up.end()) return model::Direction::Positive;
  if (std::find(down.begin(), down.end(), value) != down.end()) return model::Direction::Negative;
  csv.fail(column,
           "expected the approach direction (+, up, forward or \xE2\x86\x91; -, down, "
           "reverse or \xE2\x86\x93), got " +
               quoted(csv.field(column)));
}

// The axis column is written by hand and by laser software: any case, blanks around it.
std::optional<model::Axis> axisOf(std::string_view text) {
  std::string axis(text);
  axis.erase(0, axis.find_first_not_of(" \t"));
  axis.erase(axis.find_last_not_of(" \t") + 1);
  for (char& c : axis) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return model::axisFromName(axis);
}

void requireRunColumns(const config::CsvReader& csv) {
  const auto require = [&](bool present, const std::string& what) {
    if (!present) {
      throw ConfigError(csv.file(), "line " + std::to_string(csv.line()),
                        "the header has no " + what +
                            " column (expected target_<unit>, deviation_<unit> or "
                            "actual_<unit>, run, direction; see docs/iso230-2.md)");
    }
  };
  require(csv.has("target"), "target position (target_mm)");
  require(csv.has("deviation") || csv.has("actual"), "deviation (deviation_um) or actual position");
  require(csv.has("run"), "run");
  require(csv.has("direction"), "direction");
  if (csv.has("deviation") && csv.has("actual")) {
    throw ConfigError(csv.file(), "line " + std::to_string(csv.line()),
                      "give either a deviation column or an actual-position column, not both");
  }
}

}  // namespace

PositioningRuns parsePositioningCsv(std::istream& input, const std::string& file,
                                    std::optional<model::Axis> axisFilter) {
  PositioningRuns runs;
  runs.file = file;
  std::optional<config::CsvReader> reader;
  try {
    reader.emplace(input, file, runsSchema());
  } catch (const config::CsvNoHeader&) {
    throw ConfigError(file, "", "no header line (the file is empty)");
  }
  config::CsvReader& csv = *reader;
  requireRunColumns(csv);
  runs.ignoredColumns = csv.otherColumns();
  const int target = csv.column("target"), deviation = csv.column("deviation"),
            actual = csv.column("actual"), run = csv.column("run"),
            direction = csv.column("direction"), axisColumn = csv.column("axis");
  std::set<model::Axis> axesSeen;
  while (csv.next()) {
    if (axisColumn >= 0) {
      const std::optional<model::Axis> axis = axisOf(csv.field(axisColumn));
      if (!axis) {
        csv.fail(axisColumn, "expected the axis X, Y or Z, got " + quoted(csv.field(axisColumn)));
      }
      if (axisFilter && *axis != *axisFilter) continue;
      axesSeen.insert(*axis);
    }
    PositioningSample sample;
    sample.line = static_cast<int>(csv.line());
    sample.targetMm = csv.number(target);
    sample.deviationMm =
        deviation >= 0 ? csv.number(deviation) : csv.number(actual) - sample.targetMm;
    const double runNumber = csv.number(run);
    if (runNumber != std::floor(runNumber) || runNumber < 0 || runNumber > 1e6) {
      csv.fail(run, "expected a run number (a whole number >= 0), got " + quoted(csv.field(run)));
    }
    sample.run = static_cast<int>(runNumber);
    sample.direction = parseDirection(csv, direction);
    if (runs.samples.size() == kMaxReadings) {
      csv.fail("more than " + std::to_string(kMaxReadings) +
               " readings: not the data of one positioning test");
    }
    runs.samples.push_back(sample);
  }
  if (axesSeen.size() > 1) {
    std::string list;
    for (const model::Axis axis : axesSeen)
      list += (list.empty() ? "" : ", ") + std::string(axisName(axis));
    throw ConfigError(file, "column axis",
                      "the file holds several axes (" + list + "): choose one with --axis");
  }
  runs.axis = axisFilter;
  if (!axisFilter && !axesSeen.empty()) runs.axis = *axesSeen.begin();
  if (runs.samples.empty()) {
    throw ConfigError(file, "",
                      axisFilter ? "no readings of axis " + std::string(axisName(*axisFilter))
                                 : "no readings after the header");
  }
  return runs;
}

PositioningRuns readPositioningCsv(const std::string& path, std::optional<model::Axis> axisFilter) {
  std::ifstream input = config::openTextFile(path);
  return parsePositioningCsv(input, path, axisFilter);
}

}  // namespace volcomp::metrology
