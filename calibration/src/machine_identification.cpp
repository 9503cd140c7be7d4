// Identification of the components of a 3-axis model (see identification.hpp).
//
// Speed matters here (21 components, ~150 parameters, thousands of points), so the Jacobian is
// built from the sensitivities of the exact model to its 18 motion values at each point (finite
// differences of composeError, exact for the translations, central for the angles) times the
// basis functions of each identified component. Location errors are mapped to motion
// translations: the carriage of axis K sits at +-q_K d_K + (EXK, EYK, EZK), so changing d_K is
// exactly the same as adding +-q_K (d_K(new) - d_K(template)) to its translation, which avoids
// rebuilding the model for every parameter change.

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "instrument_frame.hpp"
#include "machine_identification.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::calibration::detail {
namespace {

using config::ConfigError;

constexpr double kFrameStep = 1e-7;

std::string powerUnit(const std::string& unit, int power) {
  if (power == 0) return unit;
  if (power == 1) return unit + "/mm";
  return unit + "/mm^" + std::to_string(power);
}

// Node count of one curve of a table basis (a bidirectional table has two curves).
int curveNodes(const IdentifySpec& spec) {
  return static_cast<int>(spec.positions.size());
}

double binomial(int n, int k) {
  double result = 1.0;
  for (int i = 1; i <= k; ++i) result = result * (n - k + i) / i;
  return result;
}

// The model reader refuses a polynomial (degree >= 1) on an axis without travel, since it would be
// extrapolated without bound: a template that would identify one is refused before any fit, so
// that calibrate never writes a model that cannot be read back.
void requireTravelForPolynomial(const IdentifySpec& spec, int axis,
                                const model::MachineModelSpec& templateSpec,
                                const std::string& file, const std::string& identifyPath) {
  if (spec.basis != IdentifySpec::Basis::Polynomial || spec.degree < 1 ||
      templateSpec.travelMm[static_cast<std::size_t>(axis)]) {
    return;
  }
  const std::string name(1, "XYZ"[axis]);
  throw ConfigError(file, identifyPath,
                    "a polynomial of degree " + std::to_string(spec.degree) +
                        " needs the travel of axis " + name + " (\"travel\": {\"" + name +
                        "\": [min, max]} in mm, the range the measurements cover): the "
                        "identified model would extrapolate it without bound and could not be "
                        "read back; give the travel, or identify a table or a constant");
}

}  // namespace

MachineIdentification::MachineIdentification(const config::ModelDocument& document,
                                             const MeasurementSet& measurements,
                                             const IdentificationOptions& options)
    : document_(document),
      template_(std::get<model::MachineModelSpec>(document.spec)),
      options_(options),
      hasAngles_(measurements.hasAngles) {
  const std::string& file = document.file;
  if (measurements.jointColumns > 0) {
    throw ConfigError(measurements.file, "line 1",
                      "joint columns q1..qN are for D-H chains; this template is a 3-axis model");
  }
  const config::ErrorUnits& units = document.units;
  std::map<std::string, int> motionByName, locationByName;
  for (int i = 0; i < 18; ++i) motionByName[model::motionName(i)] = i;
  for (int i = 0; i < 9; ++i) locationByName[model::locationName(i)] = i;

  model::MachineModelSpec base = template_;
  int parameter = 0;
  for (const auto& [keyPath, block] : document.identify) {
    const std::string prefix = "components.";
    if (keyPath.rfind(prefix, 0) != 0) {
      throw ConfigError(file, keyPath, "identify is supported for components only here");
    }
    const std::string name = keyPath.substr(prefix.size());
    const std::string identifyPath = keyPath + ".identify";
    const IdentifySpec spec = parseIdentify(block, file, identifyPath);
    if (auto location = locationByName.find(name); location != locationByName.end()) {
      if (spec.basis != IdentifySpec::Basis::Constant) {
        throw ConfigError(file, identifyPath,
                          "a location error is a constant: expected \"constant\"");
      }
      LocationParameter lp;
      lp.index = location->second;
      lp.parameter = parameter++;
      lp.start = template_.locationRad[static_cast<std::size_t>(lp.index)];
      base.locationRad[static_cast<std::size_t>(lp.index)] = 0.0;
      locations_.push_back(lp);
      info_.push_back({name, keyPath, config::unitName(units.angle), 1.0 / units.angleToRad(),
                       false, ParameterInfo::Kind::Angle});
      continue;
    }
    auto motion = motionByName.find(name);
    if (motion == motionByName.end()) {
      throw ConfigError(file, keyPath, "unknown component");
    }
    Component component;
    component.motion = motion->second;
    component.axis = motion->second / 6;
    component.spec = spec;
    component.first = parameter;
    const bool angle = motion->second % 6 >= 3;
    const std::string unit = angle ? config::unitName(units.angle) : config::unitName(units.length);
    const double toDisplay = angle ? 1.0 / units.angleToRad() : 1.0 / units.lengthToMm();
    const auto kind = angle ? ParameterInfo::Kind::Angle : ParameterInfo::Kind::Length;
    switch (spec.basis) {
      case IdentifySpec::Basis::Constant:
        component.count = 1;
        info_.push_back({name, keyPath, unit, toDisplay, false, kind});
        break;
      case IdentifySpec::Basis::Polynomial: {
        component.count = spec.degree + 1 - spec.minDegree;
        for (int k = spec.minDegree; k <= spec.degree; ++k) {
          info_.push_back({name + " c" + std::to_string(k), keyPath, powerUnit(unit, k), toDisplay,
                           false, kind, k});
        }
        break;
      }
      case IdentifySpec::Basis::Table: {
        const std::size_t nodes = spec.positions.size();
        component.count = static_cast<int>(spec.bidirectional ? 2 * nodes : nodes);
        for (std::size_t node = 0; node < spec.positions.size(); ++node) {
          // One basis function per node: the table through the unit vector, interpolated exactly
          // as the model will interpolate the identified table.
          model::TableSpec unitTable;
          unitTable.positionsMm = spec.positions;
          unitTable.values.assign(spec.positions.size(), 0.0);
          unitTable.values[node] = 1.0;
          unitTable.interpolation = spec.interpolation;
          try {
            component.nodeBasis.emplace_back(unitTable);
          } catch (const model::ModelError& e) {
            throw ConfigError(file, identifyPath, e.what());
          }
        }
        // Bidirectional tables: the positive-direction nodes ("EXX+[85]"), then the negative ones.
        for (const char* sign : spec.bidirectional ? std::vector<const char*>{"+", "-"}
                                                   : std::vector<const char*>{""}) {
          for (double position : spec.positions) {
            std::ostringstream label;
            label << name << sign << "[" << position << "]";
            info_.push_back({label.str(), keyPath, unit, toDisplay, false, kind});
          }
        }
        break;
      }
    }
    parameter += component.count;
    component.start =
        startValues(component, template_.motion[static_cast<std::size_t>(component.motion)], file,
                    keyPath + ".start");
    requireTravelForPolynomial(spec, component.axis, template_, file, identifyPath);
    base.motion[static_cast<std::size_t>(component.motion)] = 0.0;
    components_.push_back(std::move(component));
  }
  if (options.instrumentFrame) {
    frameFirst_ = parameter;
    parameter += 6;
    appendFrameInfo(info_, config::unitName(units.length), units.lengthToMm(),
                    config::unitName(units.angle), units.angleToRad());
  }
  parameterCount_ = parameter;
  for (const Component& component : components_) {
    const int nodes = curveNodes(component.spec);
    if (component.spec.smoothness > 0.0 && nodes >= 3) {
      priorRows_ += (nodes - 2) * (component.spec.bidirectional ? 2 : 1);
    }
  }

  try {
    model_.emplace(base);
  } catch (const model::ModelError& e) {
    throw ConfigError(file, "", std::string("invalid template model: ") + e.what());
  }
  workspace_ = std::make_unique<model::Workspace>();

  // Which motion values need sensitivities: identified components, and the translations of axes
  // whose location errors are identified.
  std::set<int> needed;
  for (const Component& component : components_) needed.insert(component.motion);
  for (const LocationParameter& location : locations_) {
    const int axis = location.index / 3;
    for (int t = 0; t < 3; ++t) needed.insert(axis * 6 + t);
  }
  needed_.assign(needed.begin(), needed.end());

  // Per point: template motion values, the nominal point, the tool and the basis values.
  const auto& topology = model_->topology();
  for (int k = 0; k < 3; ++k) {
    axisSign_[static_cast<std::size_t>(k)] =
        topology.isWorkpieceSide(static_cast<model::Axis>(k)) ? -1.0 : 1.0;
    baseDirection_[static_cast<std::size_t>(k)] =
        model_->axisDirection(static_cast<model::Axis>(k));
  }
  int basisWidth = 0;
  for (const Component& component : components_) basisWidth += component.count;
  basisWidth_ = basisWidth;
  points_.reserve(measurements.points.size());
  basis_.resize(measurements.points.size() * static_cast<std::size_t>(basisWidth));
  for (std::size_t i = 0; i < measurements.points.size(); ++i) {
    const Measurement& m = measurements.points[i];
    Point point = makePoint(m.qMm, measurements.hasTool ? m.toolMm : template_.toolMm, m.directions,
                            basis_.data() + i * basisWidth_);
    point.measuredMm = m.errorMm;
    point.measuredAngleRad = m.angularErrorRad;
    point.sqrtWeight = std::sqrt(m.weight);
    point.weight = m.weight;
    points_.push_back(point);
    auto group = std::find_if(toolGroups_.begin(), toolGroups_.end(),
                              [&](const ToolGroup& g) { return g.toolMm == point.toolMm; });
    if (group == toolGroups_.end()) {
      toolGroups_.push_back({point.toolMm, {}, {}, {}});
      group = toolGroups_.end() - 1;
    }
    group->points.push_back(static_cast<int>(i));
    group->qMm.push_back(point.qMm);
    group->directions.push_back(point.directions);
  }
}

MachineIdentification::Point MachineIdentification::makePoint(const Eigen::Vector3d& qMm,
                                                              const Eigen::Vector3d& toolMm,
                                                              const model::Directions& directions,
                                                              double* basisRow) const {
  Point point;
  point.qMm = qMm;
  point.toolMm = toolMm;
  point.directions = directions;
  point.nominalMm = qMm + toolMm - template_.workpieceMm;
  point.measuredMm.setZero();
  point.measuredAngleRad.setZero();
  model::evaluateMotion(*model_, qMm, directions, point.baseMotion);
  int column = 0;
  for (const Component& component : components_) {
    double q = qMm[component.axis];
    if (const auto& travel = template_.travelMm[static_cast<std::size_t>(component.axis)]) {
      q = std::clamp(q, (*travel)[0], (*travel)[1]);
    }
    evaluateBasis(component, q, directions[static_cast<std::size_t>(component.axis)],
                  basisRow + column);
    column += component.count;
  }
  return point;
}

IdentifySpec MachineIdentification::parseIdentify(const nlohmann::json& block,
                                                  const std::string& file,
                                                  const std::string& path) {
  IdentifySpec spec;
  const std::string expected =
      "\"constant\", {\"basis\": \"polynomial\", \"degree\": N} or {\"basis\": \"table\", "
      "\"positions\": [...], \"interpolation\": \"linear\"|\"cubic\"}";
  if (block.is_string()) {
    if (block.get<std::string>() != "constant") {
      throw ConfigError(file, path, "expected " + expected);
    }
    return spec;
  }
  if (!block.is_object() || !block.contains("basis") || !block.at("basis").is_string()) {
    throw ConfigError(file, path, "expected " + expected);
  }
  const std::string basis = block.at("basis").get<std::string>();
  const auto allowOnly = [&](std::initializer_list<const char*> keys) {
    for (const auto& [key, value] : block.items()) {
      bool known = false;
      for (const char* k : keys) known = known || key == k;
      if (!known) throw ConfigError(file, path + "." + key, "unknown key for basis " + basis);
    }
  };
  const auto number = [&](const char* key) {
    const nlohmann::json& value = block.at(key);
    if (!value.is_number() || !std::isfinite(value.get<double>())) {
      throw ConfigError(file, path + "." + key, "expected a finite number");
    }
    return value.get<double>();
  };
  if (basis == "constant") {
    allowOnly({"basis"});
    return spec;
  }
  if (basis == "polynomial") {
    allowOnly({"basis", "degree", "zero_at", "min_degree"});
    spec.basis = IdentifySpec::Basis::Polynomial;
    if (!block.contains("degree") || !block.at("degree").is_number_integer() ||
        block.at("degree").get<int>() < 0 || block.at("degree").get<int>() > 12) {
      throw ConfigError(file, path + ".degree", "expected an integer degree 0..12");
    }
    spec.degree = block.at("degree").get<int>();
    if (block.contains("zero_at")) {
      spec.hasZeroAt = true;
      spec.zeroAtMm = number("zero_at");
      spec.minDegree = 1;
    }
    if (block.contains("min_degree")) {
      if (!block.at("min_degree").is_number_integer() || block.at("min_degree").get<int>() < 0) {
        throw ConfigError(file, path + ".min_degree", "expected an integer >= 0");
      }
      spec.minDegree = block.at("min_degree").get<int>();
      if (spec.hasZeroAt && spec.minDegree < 1) {
        throw ConfigError(file, path + ".min_degree",
                          "with zero_at the lowest power is at least 1 (the function is 0 there)");
      }
    }
    if (spec.minDegree > spec.degree) {
      throw ConfigError(
          file, path + ".degree",
          "the degree must be at least the lowest power (" + std::to_string(spec.minDegree) + ")");
    }
    return spec;
  }
  if (basis == "table") {
    allowOnly({"basis", "positions", "interpolation", "smoothness", "bidirectional"});
    spec.basis = IdentifySpec::Basis::Table;
    if (block.contains("bidirectional")) {
      if (!block.at("bidirectional").is_boolean()) {
        throw ConfigError(file, path + ".bidirectional", "expected true or false");
      }
      spec.bidirectional = block.at("bidirectional").get<bool>();
    }
    if (!block.contains("positions") || !block.at("positions").is_array() ||
        block.at("positions").size() < 2) {
      throw ConfigError(file, path + ".positions",
                        "expected an array of at least 2 positions (mm)");
    }
    const nlohmann::json& positions = block.at("positions");
    for (std::size_t j = 0; j < positions.size(); ++j) {
      const std::string elementPath = path + ".positions[" + std::to_string(j) + "]";
      if (!positions[j].is_number() || !std::isfinite(positions[j].get<double>())) {
        throw ConfigError(file, elementPath, "expected a finite number (mm)");
      }
      const double value = positions[j].get<double>();
      if (!spec.positions.empty() && !(value > spec.positions.back())) {
        throw ConfigError(file, elementPath, "positions must be strictly increasing");
      }
      spec.positions.push_back(value);
    }
    spec.interpolation = model::Interpolation::Linear;
    if (block.contains("interpolation")) {
      const nlohmann::json& interpolation = block.at("interpolation");
      const std::string value = interpolation.is_string() ? interpolation.get<std::string>() : "";
      if (value == "linear") {
        spec.interpolation = model::Interpolation::Linear;
      } else if (value == "cubic") {
        spec.interpolation = model::Interpolation::Cubic;
      } else if (value == "quadratic") {
        spec.interpolation = model::Interpolation::Quadratic;
        if (spec.positions.size() % 2 == 0) {
          throw ConfigError(file, path + ".positions",
                            "quadratic interpolation needs an odd number of positions");
        }
      } else {
        throw ConfigError(file, path + ".interpolation",
                          "expected \"linear\", \"quadratic\" or \"cubic\"");
      }
    }
    if (block.contains("smoothness")) {
      spec.smoothness = number("smoothness");
      if (spec.smoothness < 0.0) {
        throw ConfigError(file, path + ".smoothness", "expected a weight >= 0");
      }
    }
    return spec;
  }
  throw ConfigError(file, path + ".basis",
                    "expected \"constant\", \"polynomial\" or \"table\", got \"" + basis + "\"");
}

std::vector<double> MachineIdentification::startValues(const Component& component,
                                                       const model::ErrorFunctionSpec& start,
                                                       const std::string& file,
                                                       const std::string& path) {
  std::vector<double> values(static_cast<std::size_t>(component.count), 0.0);
  const IdentifySpec& spec = component.spec;
  if (const double* constant = std::get_if<double>(&start)) {
    if (*constant == 0.0) return values;
    if (spec.basis == IdentifySpec::Basis::Table) {
      std::fill(values.begin(), values.end(), *constant);
      return values;
    }
    if (spec.minDegree == 0) {
      values[0] = *constant;
      return values;
    }
  } else if (const auto* polynomial = std::get_if<model::PolynomialSpec>(&start)) {
    if (spec.basis == IdentifySpec::Basis::Polynomial && !spec.hasZeroAt && spec.minDegree == 0 &&
        static_cast<int>(polynomial->coefficients.size()) <= spec.degree + 1) {
      std::copy(polynomial->coefficients.begin(), polynomial->coefficients.end(), values.begin());
      return values;
    }
  } else if (const auto* table = std::get_if<model::TableSpec>(&start)) {
    if (spec.basis == IdentifySpec::Basis::Table && table->positionsMm == spec.positions) {
      if (!spec.bidirectional && table->valuesNegative.empty()) return table->values;
      if (spec.bidirectional) {
        // A one-curve start serves both directions.
        const std::vector<double>& negative =
            table->valuesNegative.empty() ? table->values : table->valuesNegative;
        std::copy(table->values.begin(), table->values.end(), values.begin());
        std::copy(negative.begin(), negative.end(), values.begin() + table->values.size());
        return values;
      }
    }
  }
  throw ConfigError(file, path,
                    "the start value must be a constant or have the form of the identify basis "
                    "(same degree or same table positions; values_negative only with "
                    "\"bidirectional\": true)");
}

void MachineIdentification::evaluateBasis(const Component& component, double qMm,
                                          model::Direction direction, double* out) const {
  const IdentifySpec& spec = component.spec;
  switch (spec.basis) {
    case IdentifySpec::Basis::Constant:
      out[0] = 1.0;
      return;
    case IdentifySpec::Basis::Polynomial: {
      const double u = spec.hasZeroAt ? qMm - spec.zeroAtMm : qMm;
      double power = std::pow(u, spec.minDegree);
      for (int j = 0; j < component.count; ++j) {
        out[j] = power;
        power *= u;
      }
      return;
    }
    case IdentifySpec::Basis::Table: {
      const int nodes = curveNodes(spec);
      // The model's rule for a bidirectional table: the curve of the direction of travel, the
      // mean of both where the direction is unknown.
      double positive = 1.0, negative = 0.0;
      if (spec.bidirectional) {
        positive = direction == model::Direction::Positive   ? 1.0
                   : direction == model::Direction::Negative ? 0.0
                                                             : 0.5;
        negative = 1.0 - positive;
      }
      for (int j = 0; j < nodes; ++j) {
        const double value = component.nodeBasis[static_cast<std::size_t>(j)].value(qMm);
        out[j] = positive * value;
        if (spec.bidirectional) out[nodes + j] = negative * value;
      }
      return;
    }
  }
}

Eigen::VectorXd MachineIdentification::startVector() const {
  Eigen::VectorXd p = Eigen::VectorXd::Zero(parameterCount_);
  for (const Component& component : components_) {
    for (int j = 0; j < component.count; ++j) {
      p(component.first + j) = component.start[static_cast<std::size_t>(j)];
    }
  }
  for (const LocationParameter& location : locations_) p(location.parameter) = location.start;
  return p;
}

int MachineIdentification::residualsPerObservation() const {
  return hasAngles_ ? 6 : 3;
}

void MachineIdentification::motionValues(const double* p, const Point& point, const double* basis,
                                         model::MotionValues& values) const {
  values = point.baseMotion;
  int column = 0;
  for (const Component& component : components_) {
    double sum = 0.0;
    for (int j = 0; j < component.count; ++j) sum += p[component.first + j] * basis[column + j];
    values[static_cast<std::size_t>(component.motion)] = sum;
    column += component.count;
  }
  if (locations_.empty()) return;
  std::array<std::array<double, 3>, 3> angles{};
  std::array<bool, 3> touched{};
  for (int k = 0; k < 3; ++k) {
    for (int r = 0; r < 3; ++r) {
      angles[static_cast<std::size_t>(k)][static_cast<std::size_t>(r)] =
          model_->spec().locationRad[static_cast<std::size_t>(3 * k + r)];
    }
  }
  for (const LocationParameter& location : locations_) {
    angles[static_cast<std::size_t>(location.index / 3)]
          [static_cast<std::size_t>(location.index % 3)] = p[location.parameter];
    touched[static_cast<std::size_t>(location.index / 3)] = true;
  }
  for (int k = 0; k < 3; ++k) {
    if (!touched[static_cast<std::size_t>(k)]) continue;
    const auto& a = angles[static_cast<std::size_t>(k)];
    const Eigen::Vector3d direction = model::rotationZYX(a[0], a[1], a[2]).col(k);
    const Eigen::Vector3d shift = axisSign_[static_cast<std::size_t>(k)] * point.qMm[k] *
                                  (direction - baseDirection_[static_cast<std::size_t>(k)]);
    for (int t = 0; t < 3; ++t) values[static_cast<std::size_t>(6 * k + t)] += shift[t];
  }
}

void MachineIdentification::predict(const double* frame, const Point& point,
                                    const model::MotionValues& values, int rows,
                                    double* out) const {
  const model::PointError error =
      model::composeError(*model_, *workspace_, point.qMm, values, point.toolMm);
  const Eigen::Vector3d position = predictedPositionError(frame, point.nominalMm, error.errorMm);
  for (int t = 0; t < 3; ++t) out[t] = position[t];
  if (rows > 3) {
    const Eigen::Vector3d angle = predictedAngularError(frame, error.angularErrorRad);
    for (int t = 0; t < 3; ++t) out[3 + t] = angle[t];
  }
}

void MachineIdentification::observationResiduals(const double* p, int i, double* r) const {
  const Point& point = points_[static_cast<std::size_t>(i)];
  model::MotionValues values;
  motionValues(p, point, basis_.data() + static_cast<std::size_t>(i) * basisWidth_, values);
  const double* frame = frameFirst_ >= 0 ? p + frameFirst_ : nullptr;
  predict(frame, point, values, residualsPerObservation(), r);
  for (int t = 0; t < 3; ++t) r[t] = (r[t] - point.measuredMm[t]) * point.sqrtWeight;
  if (hasAngles_) {
    for (int t = 0; t < 3; ++t) {
      r[3 + t] = (r[3 + t] - point.measuredAngleRad[t]) * point.sqrtWeight * options_.angleScaleMm;
    }
  }
}

void MachineIdentification::observationJacobian(const double* p, int i, double* jacobian) const {
  const Point& point = points_[static_cast<std::size_t>(i)];
  const int rows = residualsPerObservation();
  const int n = parameterCount_;
  jacobianAt(p, point, basis_.data() + static_cast<std::size_t>(i) * basisWidth_, rows, true,
             jacobian);
  for (int row = 0; row < rows; ++row) {
    const double scale = point.sqrtWeight * (row >= 3 ? options_.angleScaleMm : 1.0);
    for (int j = 0; j < n; ++j) jacobian[row * n + j] *= scale;
  }
}

Eigen::Vector3d MachineIdentification::locationDirectionDerivative(
    const LocationParameter& location, const double* p) const {
  const int axis = location.index / 3;
  std::array<double, 3> angles{};
  for (int r = 0; r < 3; ++r) {
    angles[static_cast<std::size_t>(r)] =
        model_->spec().locationRad[static_cast<std::size_t>(3 * axis + r)];
  }
  for (const LocationParameter& other : locations_) {
    if (other.index / 3 == axis) {
      angles[static_cast<std::size_t>(other.index % 3)] = p[other.parameter];
    }
  }
  std::array<double, 3> up = angles, down = angles;
  up[static_cast<std::size_t>(location.index % 3)] += kRotationStepRad;
  down[static_cast<std::size_t>(location.index % 3)] -= kRotationStepRad;
  return (model::rotationZYX(up[0], up[1], up[2]).col(axis) -
          model::rotationZYX(down[0], down[1], down[2]).col(axis)) /
         (2.0 * kRotationStepRad) * axisSign_[static_cast<std::size_t>(axis)];
}

void MachineIdentification::jacobianAt(const double* p, const Point& point, const double* basis,
                                       int rows, bool instrument, double* jacobian) const {
  const int n = parameterCount_;
  std::fill(jacobian, jacobian + rows * n, 0.0);
  model::MotionValues values;
  motionValues(p, point, basis, values);
  const double* frame = instrument && frameFirst_ >= 0 ? p + frameFirst_ : nullptr;
  std::array<double, 6> centre{}, plus{}, minus{};
  predict(frame, point, values, rows, centre.data());

  // Sensitivity of the predicted rows to each needed motion value.
  std::array<std::array<double, 6>, 18> sensitivity{};
  for (int c : needed_) {
    const bool rotation = c % 6 >= 3;
    const double saved = values[static_cast<std::size_t>(c)];
    auto& column = sensitivity[static_cast<std::size_t>(c)];
    if (rotation) {
      values[static_cast<std::size_t>(c)] = saved + kRotationStepRad;
      predict(frame, point, values, rows, plus.data());
      values[static_cast<std::size_t>(c)] = saved - kRotationStepRad;
      predict(frame, point, values, rows, minus.data());
      for (int row = 0; row < rows; ++row) {
        column[static_cast<std::size_t>(row)] =
            (plus[static_cast<std::size_t>(row)] - minus[static_cast<std::size_t>(row)]) /
            (2.0 * kRotationStepRad);
      }
    } else {
      // The position is affine in a translation: a forward difference is exact.
      values[static_cast<std::size_t>(c)] = saved + kTranslationStepMm;
      predict(frame, point, values, rows, plus.data());
      for (int row = 0; row < rows; ++row) {
        column[static_cast<std::size_t>(row)] =
            (plus[static_cast<std::size_t>(row)] - centre[static_cast<std::size_t>(row)]) /
            kTranslationStepMm;
      }
    }
    values[static_cast<std::size_t>(c)] = saved;
  }

  int basisColumn = 0;
  for (const Component& component : components_) {
    const auto& column = sensitivity[static_cast<std::size_t>(component.motion)];
    for (int j = 0; j < component.count; ++j) {
      const double b = basis[basisColumn + j];
      for (int row = 0; row < rows; ++row) {
        jacobian[row * n + component.first + j] = column[static_cast<std::size_t>(row)] * b;
      }
    }
    basisColumn += component.count;
  }
  for (const LocationParameter& location : locations_) {
    const int axis = location.index / 3;
    const Eigen::Vector3d derivative = locationDirectionDerivative(location, p) * point.qMm[axis];
    for (int row = 0; row < rows; ++row) {
      double sum = 0.0;
      for (int t = 0; t < 3; ++t) {
        sum += sensitivity[static_cast<std::size_t>(6 * axis + t)][static_cast<std::size_t>(row)] *
               derivative[t];
      }
      jacobian[row * n + location.parameter] = sum;
    }
  }
  if (frame != nullptr) {
    std::array<double, 6> frameValues{};
    for (int f = 0; f < 6; ++f) frameValues[static_cast<std::size_t>(f)] = frame[f];
    const model::PointError error =
        model::composeError(*model_, *workspace_, point.qMm, values, point.toolMm);
    for (int f = 0; f < 6; ++f) {
      const double step = f < 3 ? kFrameStep : kTranslationStepMm;
      std::array<double, 6> up = frameValues, down = frameValues;
      up[static_cast<std::size_t>(f)] += step;
      down[static_cast<std::size_t>(f)] -= step;
      const Eigen::Vector3d dPosition =
          (predictedPositionError(up.data(), point.nominalMm, error.errorMm) -
           predictedPositionError(down.data(), point.nominalMm, error.errorMm)) /
          (2.0 * step);
      for (int t = 0; t < 3; ++t) jacobian[t * n + frameFirst_ + f] = dPosition[t];
      if (rows > 3) {
        const Eigen::Vector3d dAngle = (predictedAngularError(up.data(), error.angularErrorRad) -
                                        predictedAngularError(down.data(), error.angularErrorRad)) /
                                       (2.0 * step);
        for (int t = 0; t < 3; ++t) jacobian[(3 + t) * n + frameFirst_ + f] = dAngle[t];
      }
    }
  }
}

void MachineIdentification::prediction(const Eigen::VectorXd& p, const PredictionPoint& at,
                                       Eigen::Vector3d& errorMm,
                                       Eigen::Ref<Eigen::MatrixXd> jacobian) const {
  std::vector<double> basis(basisWidth_);
  const Point point =
      makePoint(at.qMm, at.toolMm.value_or(template_.toolMm), at.directions, basis.data());
  model::MotionValues values;
  motionValues(p.data(), point, basis.data(), values);
  predict(nullptr, point, values, 3, errorMm.data());
  Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor> rows(3, parameterCount_);
  jacobianAt(p.data(), point, basis.data(), 3, false, rows.data());
  jacobian = rows;
}

std::vector<Curve> MachineIdentification::curves() const {
  std::vector<Curve> out;
  for (const Component& component : components_) {
    const ParameterInfo& info = info_[static_cast<std::size_t>(component.first)];
    const IdentifySpec& spec = component.spec;
    std::vector<double> positions;
    if (spec.basis == IdentifySpec::Basis::Table) {
      positions = spec.positions;
    } else if (const auto& travel = template_.travelMm[static_cast<std::size_t>(component.axis)]) {
      for (int k = 0; k <= 4; ++k) {
        positions.push_back((*travel)[0] + ((*travel)[1] - (*travel)[0]) * k / 4.0);
      }
    } else {
      // Without a travel the function's own reference is all there is: where it is zero, if
      // anywhere, else the origin.
      positions.push_back(spec.hasZeroAt ? spec.zeroAtMm : 0.0);
    }
    Curve base;
    base.component = model::motionName(component.motion);
    base.unit = info.unit;
    base.toDisplay = info.toDisplay;
    base.angle = info.kind == ParameterInfo::Kind::Angle;
    base.positionsMm = positions;
    std::vector<model::Direction> directions{model::Direction::Unknown};
    if (spec.bidirectional) directions = {model::Direction::Positive, model::Direction::Negative};
    std::vector<Curve> perDirection;
    for (model::Direction direction : directions) {
      Curve curve = base;
      if (spec.bidirectional) {
        curve.direction = direction == model::Direction::Positive ? CurveDirection::Positive
                                                                  : CurveDirection::Negative;
      }
      std::vector<double> basis(static_cast<std::size_t>(component.count));
      for (double q : positions) {
        evaluateBasis(component, q, direction, basis.data());
        Eigen::RowVectorXd g = Eigen::RowVectorXd::Zero(parameterCount_);
        for (int j = 0; j < component.count; ++j) {
          g(component.first + j) = basis[static_cast<std::size_t>(j)];
        }
        curve.gradients.push_back(std::move(g));
      }
      perDirection.push_back(std::move(curve));
    }
    if (spec.bidirectional) {
      Curve reversal = base;
      reversal.direction = CurveDirection::Reversal;
      for (std::size_t k = 0; k < positions.size(); ++k) {
        reversal.gradients.push_back(perDirection[1].gradients[k] - perDirection[0].gradients[k]);
      }
      perDirection.push_back(std::move(reversal));
    }
    for (Curve& curve : perDirection) out.push_back(std::move(curve));
  }
  return out;
}

int MachineIdentification::priorRowCount() const {
  return priorRows_;
}

void MachineIdentification::priorResiduals(const double* p, double* r) const {
  int row = 0;
  for (const Component& component : components_) {
    const int nodes = curveNodes(component.spec);
    if (!(component.spec.smoothness > 0.0) || nodes < 3) continue;
    const double weight = std::sqrt(component.spec.smoothness);
    for (int curve = 0; curve < component.count / nodes; ++curve) {
      const double* v = p + component.first + curve * nodes;
      for (int j = 1; j + 1 < nodes; ++j) {
        r[row++] = weight * (v[j - 1] - 2.0 * v[j] + v[j + 1]);
      }
    }
  }
}

void MachineIdentification::priorJacobian(const double*, double* jacobian) const {
  const int n = parameterCount_;
  std::fill(jacobian, jacobian + priorRows_ * n, 0.0);
  int row = 0;
  for (const Component& component : components_) {
    const int nodes = curveNodes(component.spec);
    if (!(component.spec.smoothness > 0.0) || nodes < 3) continue;
    const double weight = std::sqrt(component.spec.smoothness);
    for (int curve = 0; curve < component.count / nodes; ++curve) {
      const int first = component.first + curve * nodes;
      for (int j = 1; j + 1 < nodes; ++j) {
        jacobian[row * n + first + j - 1] = weight;
        jacobian[row * n + first + j] = -2.0 * weight;
        jacobian[row * n + first + j + 1] = weight;
        ++row;
      }
    }
  }
}

double MachineIdentification::observationWeight(int i) const {
  return points_[static_cast<std::size_t>(i)].weight;
}

model::MachineModelSpec MachineIdentification::identifiedSpec(const Eigen::VectorXd& p) const {
  model::MachineModelSpec spec = template_;
  for (const Component& component : components_) {
    const double* v = p.data() + component.first;
    model::ErrorFunctionSpec function;
    switch (component.spec.basis) {
      case IdentifySpec::Basis::Constant:
        function = v[0];
        break;
      case IdentifySpec::Basis::Polynomial: {
        // sum_k c_k (q - z)^k = sum_m [sum_{k >= m} c_k C(k, m) (-z)^(k - m)] q^m.
        const int degree = component.spec.degree;
        const double z = component.spec.hasZeroAt ? component.spec.zeroAtMm : 0.0;
        const int lowest = component.spec.minDegree;
        model::PolynomialSpec polynomial;
        polynomial.coefficients.assign(static_cast<std::size_t>(degree + 1), 0.0);
        for (int k = lowest; k <= degree; ++k) {
          for (int m = 0; m <= k; ++m) {
            polynomial.coefficients[static_cast<std::size_t>(m)] +=
                v[k - lowest] * binomial(k, m) * std::pow(-z, k - m);
          }
        }
        function = polynomial;
        break;
      }
      case IdentifySpec::Basis::Table: {
        const int nodes = curveNodes(component.spec);
        model::TableSpec table;
        table.positionsMm = component.spec.positions;
        table.values.assign(v, v + nodes);
        if (component.spec.bidirectional) table.valuesNegative.assign(v + nodes, v + 2 * nodes);
        table.interpolation = component.spec.interpolation;
        function = table;
        break;
      }
    }
    spec.motion[static_cast<std::size_t>(component.motion)] = function;
  }
  for (const LocationParameter& location : locations_) {
    spec.locationRad[static_cast<std::size_t>(location.index)] = p(location.parameter);
  }
  return spec;
}

nlohmann::json MachineIdentification::modelJson(const Eigen::VectorXd& p) const {
  return config::writeModel(identifiedSpec(p), document_.units);
}

}  // namespace volcomp::calibration::detail
