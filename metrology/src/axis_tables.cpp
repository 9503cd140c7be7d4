#include "volcomp/metrology/axis_tables.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace volcomp::metrology {

const char* axisName(model::Axis axis) noexcept {
  return axis == model::Axis::X ? "X" : (axis == model::Axis::Y ? "Y" : "Z");
}

bool isPresent(const model::ErrorFunctionSpec& function) {
  if (const double* constant = std::get_if<double>(&function)) return *constant != 0.0;
  return true;
}

bool isBidirectional(const model::ErrorFunctionSpec& function) {
  const auto* table = std::get_if<model::TableSpec>(&function);
  return table != nullptr && !table->valuesNegative.empty();
}

double AxisTable::errorAt(double qMm) const noexcept {
  if (errorMm.empty()) return 0.0;
  const double u = (qMm - grid.startMm) / grid.stepMm;
  if (!(u > 0.0)) return errorMm.front();
  const auto last = static_cast<double>(errorMm.size() - 1);
  if (u >= last) return errorMm.back();
  const auto i = static_cast<std::size_t>(u);
  const double t = u - static_cast<double>(i);
  return errorMm[i] + t * (errorMm[i + 1] - errorMm[i]);
}

AxisRange axisRange(const model::MachineModelSpec& spec, model::Axis axis) {
  const auto k = static_cast<std::size_t>(axis);
  if (spec.travelMm[k]) return {(*spec.travelMm[k])[0], (*spec.travelMm[k])[1], true};
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (int kind = 0; kind < 6; ++kind) {
    const auto& function =
        spec.motion[static_cast<std::size_t>(model::motionIndex(axis, model::MotionKind(kind)))];
    if (const auto* table = std::get_if<model::TableSpec>(&function)) {
      low = std::min(low, table->positionsMm.front());
      high = std::max(high, table->positionsMm.back());
    }
  }
  if (low > high) return {0.0, 0.0, false};
  return {low, high, false};
}

AxisGrid makeGrid(const AxisRange& range, double stepMm) {
  const double length = range.highMm - range.lowMm;
  AxisGrid grid;
  grid.startMm = range.lowMm;
  if (length <= 0.0) {
    grid.stepMm = stepMm > 0.0 ? stepMm : 1.0;
    grid.count = 1;
    return grid;
  }
  if (stepMm <= 0.0) {
    // The smallest "round" step with at most 100 intervals: tables stay short enough for every
    // controller here (LinuxCNC takes 256 points) and readable by a person.
    const double raw = length / 100.0;
    const double decade = std::pow(10.0, std::floor(std::log10(raw)));
    stepMm = 10.0 * decade;
    for (double factor : {1.0, 2.0, 2.5, 5.0}) {
      if (factor * decade >= raw * (1.0 - 1e-12)) {
        stepMm = factor * decade;
        break;
      }
    }
  }
  grid.stepMm = stepMm;
  grid.count = static_cast<std::size_t>(std::ceil(length / stepMm - 1e-9)) + 1;
  return grid;
}

AxisTable sampleTable(const model::MachineModelSpec& spec, const std::vector<int>& motion,
                      const std::vector<int>& location, model::Axis input, model::Axis output,
                      const AxisGrid& grid, model::Direction direction) {
  // A model holding only these components; its travel stays, so that clamping matches the full
  // model's, while the grid may run past the travel (held values there, as the controllers do).
  model::MachineModelSpec only;
  only.topology = spec.topology;
  only.travelMm = spec.travelMm;
  only.toolMm = spec.toolMm;
  only.workpieceMm = spec.workpieceMm;
  AxisTable table;
  table.input = input;
  table.output = output;
  table.direction = static_cast<int>(direction);
  table.grid = grid;
  for (int index : motion) {
    only.motion[static_cast<std::size_t>(index)] = spec.motion[static_cast<std::size_t>(index)];
    table.components.push_back(model::motionName(index));
  }
  for (int index : location) {
    only.locationRad[static_cast<std::size_t>(index)] =
        spec.locationRad[static_cast<std::size_t>(index)];
    table.components.push_back(model::locationName(index));
  }
  const model::MachineModel subModel(only);
  model::Workspace ws;
  model::Directions directions{};
  directions[static_cast<std::size_t>(input)] = direction;
  const auto k = static_cast<Eigen::Index>(input);
  Eigen::Vector3d q = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < 3; ++a) {
    if (spec.travelMm[static_cast<std::size_t>(a)]) {
      q[a] = (*spec.travelMm[static_cast<std::size_t>(a)])[0];
    }
  }
  table.errorMm.reserve(grid.count);
  for (std::size_t i = 0; i < grid.count; ++i) {
    q[k] = grid.positionMm(i);
    const model::PointError e = model::evaluate(subModel, ws, q, directions);
    table.errorMm.push_back(e.errorMm[static_cast<Eigen::Index>(output)]);
  }
  return table;
}

}  // namespace volcomp::metrology
