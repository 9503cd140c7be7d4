#include <algorithm>
#include <utility>

#include "model_file_parts.hpp"

namespace volcomp::config::detail {
namespace {

using model::ErrorFunctionSpec;

constexpr const char* kAxisNames[3] = {"X", "Y", "Z"};

const std::array<std::string, 18> kMotionNames = [] {
  std::array<std::string, 18> names;
  const char kinds[] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
  for (int axis = 0; axis < 3; ++axis) {
    for (int kind = 0; kind < 6; ++kind) {
      names[axis * 6 + kind] = std::string("E") + kinds[kind] + kAxisNames[axis];
    }
  }
  return names;
}();

const std::array<std::string, 9> kLocationNames = [] {
  std::array<std::string, 9> names;
  const char rotations[] = {'A', 'B', 'C'};
  for (int axis = 0; axis < 3; ++axis) {
    for (int r = 0; r < 3; ++r) {
      names[axis * 3 + r] = std::string("E") + rotations[r] + "0" + kAxisNames[axis];
    }
  }
  return names;
}();

std::vector<double> scaled(std::vector<double> values, double factor) {
  for (double& v : values) v *= factor;
  return values;
}

model::Interpolation readInterpolation(const JsonReader& node) {
  const std::string s = node.oneOf({"linear", "quadratic", "cubic"});
  if (s == "quadratic") return model::Interpolation::Quadratic;
  if (s == "cubic") return model::Interpolation::Cubic;
  return model::Interpolation::Linear;
}

std::vector<double> readValues(const JsonReader& node, std::size_t count, double factor) {
  if (!node.isArray() || node.size() != count) {
    node.failExpected("an array of " + std::to_string(count) + " numbers (one per position)");
  }
  return scaled(node.numbers(count), factor);
}

ErrorFunctionSpec readTable(const JsonReader& node, double factor) {
  node.allowOnly({"positions", "values", "values_negative", "interpolation"});
  model::TableSpec table;
  if (const auto interp = node.find("interpolation"))
    table.interpolation = readInterpolation(*interp);
  const JsonReader positions = node.at("positions");
  table.positionsMm = readIncreasing(positions, 2);
  const std::size_t n = table.positionsMm.size();
  if (table.interpolation == model::Interpolation::Quadratic && n % 2 == 0) {
    positions.fail(
        "expected an odd number of positions (>= 3) for quadratic interpolation "
        "(3-node elements 0-1-2, 2-3-4, ...), got " +
        std::to_string(n));
  }
  table.values = readValues(node.at("values"), n, factor);
  if (const auto negative = node.find("values_negative")) {
    table.valuesNegative = readValues(*negative, n, factor);
  }
  return table;
}

ErrorFunctionSpec readErrorFunction(const JsonReader& node, double factor, const Context& ctx) {
  if (node.isNumber()) return node.number() * factor;
  if (!node.isObject()) {
    node.failExpected(
        "a number, a table {\"positions\", \"values\", \"interpolation\"} or "
        "{\"polynomial\": [c0, c1, ...]}");
  }
  if (const auto block = readIdentifyBlock(node, ctx.options, ctx.doc)) {
    if (!block->start) return 0.0;
    if (block->start->isObject() && block->start->has("identify"))
      block->start->fail("a start value cannot be identified");
    return readErrorFunction(*block->start, factor, ctx);
  }
  if (node.has("polynomial")) {
    node.allowOnly({"polynomial"});
    const JsonReader coefficients = node.at("polynomial");
    coefficients.elements(1);
    // Coefficients of every power give values in error units, so all of them scale.
    return model::PolynomialSpec{scaled(coefficients.numbers(), factor)};
  }
  return readTable(node, factor);
}

double readLocation(const JsonReader& node, double factor, const Context& ctx) {
  if (const auto block = readIdentifyBlock(node, ctx.options, ctx.doc)) {
    return block->start ? block->start->number() * factor : 0.0;
  }
  if (!node.isNumber()) {
    node.failExpected("a number (a location error is a constant angle)");
  }
  return node.number() * factor;
}

std::string readTopology(const JsonReader& node) {
  const std::string expected =
      "a topology string such as \"XYFZ\" (F once and each of X, Y, Z once, upper case)";
  if (!node.isString()) node.failExpected(expected);
  const std::string text = node.string();
  std::string sorted = text;
  std::sort(sorted.begin(), sorted.end());
  if (sorted != "FXYZ") node.failExpected(expected);
  return text;
}

void readTravel(const JsonReader& node, model::MachineModelSpec& spec) {
  node.allowOnly({"X", "Y", "Z"});
  for (int axis = 0; axis < 3; ++axis) {
    const auto range = node.find(kAxisNames[axis]);
    if (!range) continue;
    if (!range->isArray() || range->size() != 2) range->failExpected("[min, max] in mm");
    const auto v = range->fixedNumbers<2>();
    if (!(v[0] < v[1])) range->failExpected("[min, max] with min < max");
    spec.travelMm[axis] = v;
  }
}

Eigen::Vector3d readVector3(const JsonReader& node) {
  if (!node.isArray() || node.size() != 3) node.failExpected("[x, y, z] in mm");
  const auto v = node.fixedNumbers<3>();
  return {v[0], v[1], v[2]};
}

ErrorUnits readUnits(const JsonReader& node) {
  node.allowOnly({"length", "angle"});
  ErrorUnits units;
  // oneOf refuses, naming file, key and choices, any name the units do not have.
  if (const auto length = node.find("length")) {
    units.length = lengthUnitFromName(length->oneOf({"mm", "um", "nm"})).value();
  }
  if (const auto angle = node.find("angle")) {
    units.angle = angleUnitFromName(angle->oneOf({"rad", "mrad", "urad", "arcsec", "deg"})).value();
  }
  return units;
}

PlausibilityLimits readPlausibility(const JsonReader& node) {
  node.allowOnly({"max_length_mm", "max_angle_rad"});
  PlausibilityLimits limits;
  limits.stated = true;
  if (const auto v = node.find("max_length_mm")) limits.maxLengthMm = v->number(1e-9, 1000.0);
  if (const auto v = node.find("max_angle_rad")) limits.maxAngleRad = v->number(1e-12, 1.0);
  return limits;
}

// A polynomial grows without bound outside the range it was fitted on; only the axis' travel
// bounds where it is evaluated (the model holds every error function at the travel ends).
// A calibration template's start value is not evaluated on a machine: identify blocks pass.
void requireBoundedPolynomials(const JsonReader& components, const model::MachineModelSpec& spec,
                               const ModelDocument& doc) {
  for (int i = 0; i < 18; ++i) {
    const auto* p = std::get_if<model::PolynomialSpec>(&spec.motion[i]);
    const int axis = i / 6;
    if (p == nullptr || p->coefficients.size() < 2 || spec.travelMm[axis]) continue;
    if (doc.identify.count(components.childPath(kMotionNames[i])) != 0) continue;
    components.at(kMotionNames[i])
        .fail(std::string("a polynomial needs the travel of axis ") + kAxisNames[axis] +
              " (\"travel\": {\"" + kAxisNames[axis] +
              "\": [min, max]} in mm): without it the polynomial would be extrapolated without "
              "bound; give the travel it was measured over, or use a table");
  }
}

void readComponents(const JsonReader& node, model::MachineModelSpec& spec, const Context& ctx) {
  node.expectObject();
  for (const auto& [name, value] : node.members()) {
    bool known = false;
    for (int i = 0; i < 18 && !known; ++i) {
      if (name != kMotionNames[i]) continue;
      known = true;
      const bool translation = i % 6 < 3;
      spec.motion[i] = readErrorFunction(
          value, translation ? ctx.doc.units.lengthToMm() : ctx.doc.units.angleToRad(), ctx);
    }
    for (int i = 0; i < 9 && !known; ++i) {
      if (name != kLocationNames[i]) continue;
      known = true;
      spec.locationRad[i] = readLocation(value, ctx.doc.units.angleToRad(), ctx);
    }
    if (!known) {
      value.fail(
          "unknown component; expected an ISO 230-1 name: EXX, EYX, EZX, EAX, EBX, ECX "
          "(and the same for Y and Z) or a location error EA0X, EB0X, EC0X, EA0Y, ..., EC0Z");
    }
  }
}

model::Axis readAxis(const JsonReader& node) {
  const std::string s = node.oneOf({"X", "Y", "Z"});
  return s == "X" ? model::Axis::X : s == "Y" ? model::Axis::Y : model::Axis::Z;
}

// values nested in the order of `over`; flattened row-major (last axis fastest).
void readGridValues(const JsonReader& node, const std::vector<std::vector<double>>& axes,
                    std::size_t level, double factor, std::vector<double>& out) {
  const std::size_t n = axes[level].size();
  const std::string what = level + 1 == axes.size() ? " numbers" : " arrays";
  if (!node.isArray() || node.size() != n) {
    node.failExpected("an array of " + std::to_string(n) + what + " (one per node of axis " +
                      std::to_string(level + 1) + " of \"over\")");
  }
  for (const JsonReader& element : node.elements()) {
    if (level + 1 == axes.size()) {
      out.push_back(element.number() * factor);
    } else {
      readGridValues(element, axes, level + 1, factor, out);
    }
  }
}

model::GridSpec readGrid(const JsonReader& node, const Context& ctx) {
  node.allowOnly({"component", "over", "axes", "values"});
  model::GridSpec grid;
  const std::string component = node.at("component").oneOf({"EX", "EY", "EZ"});
  grid.component = component == "EX" ? 0 : component == "EY" ? 1 : 2;
  const JsonReader over = node.at("over");
  std::vector<std::string> overNames;
  for (const JsonReader& axis : over.elements(2, 3)) {
    const model::Axis a = readAxis(axis);
    const std::string name = kAxisNames[static_cast<int>(a)];
    for (const std::string& previous : overNames) {
      if (previous == name) axis.failExpected("an axis not already listed in \"over\"");
    }
    overNames.push_back(name);
    grid.over.push_back(a);
  }
  const JsonReader axes = node.at("axes");
  axes.allowOnly(overNames);
  for (const std::string& name : overNames) grid.axesMm.push_back(readIncreasing(axes.at(name), 2));
  readGridValues(node.at("values"), grid.axesMm, 0, ctx.doc.units.lengthToMm(), grid.valuesMm);
  return grid;
}

}  // namespace

const std::array<std::string, 18>& motionNames() {
  return kMotionNames;
}
const std::array<std::string, 9>& locationNames() {
  return kLocationNames;
}

std::optional<IdentifyBlock> readIdentifyBlock(const JsonReader& node, const ParseOptions& options,
                                               ModelDocument& doc) {
  if (!node.isObject() || !node.has("identify")) return std::nullopt;
  if (!options.allowIdentify) {
    throw ConfigError(node.file(), node.childPath("identify"),
                      "unknown key (\"identify\" is allowed in calibration templates only)");
  }
  node.allowOnly({"identify", "start"});
  doc.identify[node.path()] = node.at("identify").json();
  return IdentifyBlock{node.find("start")};
}

std::vector<double> readIncreasing(const JsonReader& node, std::size_t minCount) {
  node.elements(minCount);
  const std::vector<double> values = node.numbers();
  for (std::size_t i = 1; i < values.size(); ++i) {
    if (!(values[i] > values[i - 1])) {
      JsonReader(node.json()[i], node.file(), node.elementPath(i))
          .failExpected("a position greater than the previous one (" +
                        nlohmann::json(values[i - 1]).dump() +
                        "): positions must increase strictly");
    }
  }
  return values;
}

void parseMachineDocument(const JsonReader& root, const ParseOptions& options, ModelDocument& doc) {
  root.allowOnly({"format", "name", "description", "topology", "travel", "tool", "workpiece",
                  "error_units", "plausibility", "components", "grids", "calibration"});
  const Context ctx{options, doc};
  model::MachineModelSpec spec;
  spec.name = root.stringOr("name", "");
  if (const auto description = root.find("description")) description->string();
  spec.topology = readTopology(root.at("topology"));
  if (const auto travel = root.find("travel")) readTravel(*travel, spec);
  if (const auto tool = root.find("tool")) spec.toolMm = readVector3(*tool);
  if (const auto workpiece = root.find("workpiece")) spec.workpieceMm = readVector3(*workpiece);
  // Units first: components and grids are scaled by them.
  if (const auto units = root.find("error_units")) {
    doc.units = readUnits(*units);
    doc.unitsStated = true;
  }
  if (const auto limits = root.find("plausibility")) doc.plausibility = readPlausibility(*limits);
  if (const auto components = root.find("components")) {
    readComponents(*components, spec, ctx);
    requireBoundedPolynomials(*components, spec, doc);
  }
  if (const auto grids = root.find("grids")) {
    for (const JsonReader& grid : grids->elements()) spec.grids.push_back(readGrid(grid, ctx));
  }
  if (const auto calibration = root.find("calibration")) {
    doc.calibration = readCalibrationRecord(*calibration);
  }
  doc.spec = std::move(spec);
}

}  // namespace volcomp::config::detail
