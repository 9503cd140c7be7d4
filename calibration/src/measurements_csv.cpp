#include "volcomp/calibration/measurements.hpp"

#include <fstream>
#include <string>

#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/printable.hpp"

namespace volcomp::calibration {
namespace {

using config::ConfigError;
using config::CsvQuantity;

// A calibration with more points than this needs a Jacobian of several GB; a file with more rows
// is refused while it is read, before the memory is spent.
constexpr std::size_t kMaxMeasurements = 1000000;

constexpr int kMaxJoints = 9;

config::CsvSchema measurementSchema() {
  config::CsvSchema schema;
  schema.add({"x", "y", "z", "ex", "ey", "ez"}, CsvQuantity::Length, true)
      .addGroup({"tx", "ty", "tz"}, CsvQuantity::Length)
      .addGroup({"ea", "eb", "ec"}, CsvQuantity::Angle)
      .add({"weight"}, CsvQuantity::Number)
      .add({"direction"}, CsvQuantity::Direction)
      .add({"q1", "q2", "q3", "q4", "q5", "q6", "q7", "q8", "q9"}, CsvQuantity::Number)
      // `volcomp eval --points` output can be read back: its offsets are not measurements.
      .ignore({"ox", "oy", "oz"});
  return schema;
}

}  // namespace

MeasurementSet parseMeasurementsCsv(std::istream& input, const std::string& file) {
  config::CsvReader csv(input, file, measurementSchema());
  MeasurementSet set;
  set.file = file;
  set.hasTool = csv.has("tx");
  set.hasAngles = csv.has("ea");
  set.hasDirection = csv.has("direction");
  std::vector<int> joints;
  for (int j = 1; j <= kMaxJoints; ++j) {
    const int column = csv.column("q" + std::to_string(j));
    if (column < 0) continue;
    if (j != set.jointColumns + 1) {
      throw ConfigError(file, "line " + std::to_string(csv.line()),
                        "joint columns must be q1..qN without gaps");
    }
    set.jointColumns = j;
    joints.push_back(column);
  }
  const int x = csv.column("x"), y = csv.column("y"), z = csv.column("z");
  const int ex = csv.column("ex"), ey = csv.column("ey"), ez = csv.column("ez");
  const int weight = csv.column("weight"), direction = csv.column("direction");
  while (csv.next()) {
    Measurement m;
    m.line = static_cast<int>(csv.line());
    m.qMm = {csv.number(x), csv.number(y), csv.number(z)};
    m.errorMm = {csv.number(ex), csv.number(ey), csv.number(ez)};
    if (set.hasTool) m.toolMm = {csv.number("tx"), csv.number("ty"), csv.number("tz")};
    if (set.hasAngles) m.angularErrorRad = {csv.number("ea"), csv.number("eb"), csv.number("ec")};
    if (direction >= 0) m.directions = csv.directions(direction);
    for (int column : joints) m.joints.push_back(csv.number(column));
    if (weight >= 0) {
      m.weight = csv.number(weight);
      if (!(m.weight > 0.0)) {
        csv.fail(weight, "expected a weight > 0, got " + config::quoted(csv.field(weight)));
      }
    }
    if (set.points.size() == kMaxMeasurements) {
      csv.fail("more than " + std::to_string(kMaxMeasurements) +
               " measurements: thin the data out before calibrating");
    }
    set.points.push_back(std::move(m));
  }
  if (set.points.empty()) throw ConfigError(file, "", "no measurement rows after the header");
  return set;
}

MeasurementSet readMeasurementsCsv(const std::string& path) {
  std::ifstream input = config::CsvReader::open(path);
  return parseMeasurementsCsv(input, path);
}

}  // namespace volcomp::calibration
