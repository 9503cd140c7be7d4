#include "volcomp/metrology/export_plan.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "volcomp/format/numbers.hpp"

namespace volcomp::metrology {
namespace {

using model::Axis;
using model::Direction;

constexpr std::array<Axis, 3> kAxes{Axis::X, Axis::Y, Axis::Z};

int positioningIndex(Axis axis) {
  return model::motionIndex(axis, static_cast<model::MotionKind>(axis));
}

/// The location error of axis K that tilts its line of motion towards L (K != L): the rotation
/// about the third axis M (EC0Y tilts Y towards X).
int squarenessIndex(Axis input, Axis output) {
  const int m = 3 - static_cast<int>(input) - static_cast<int>(output);
  return model::locationIndex(input, m);
}

std::string gridText(const AxisGrid& grid) {
  return std::to_string(grid.count) + " points every " + format::general(grid.stepMm) +
         " mm over [" + format::general(grid.startMm) + ", " + format::general(grid.endMm()) +
         "] mm";
}

/// Lines for every component present in the model that is not in `carried`.
void listNotCarried(const model::MachineModelSpec& spec, const std::set<std::string>& carried,
                    const std::string& translationReason, const std::string& squarenessReason,
                    ExportPlan& plan) {
  for (int index = 0; index < 18; ++index) {
    const std::string name = model::motionName(index);
    if (!isPresent(spec.motion[static_cast<std::size_t>(index)]) || carried.count(name)) continue;
    const int kind = index % 6;
    if (kind >= 3) {
      plan.notCarried.push_back(name +
                                ": angular error motion; its Abbe error depends on the other "
                                "axes' positions and the tool length, which no 1-D table sees");
    } else {
      plan.notCarried.push_back(name + ": " + translationReason);
    }
  }
  for (int index = 0; index < 9; ++index) {
    const std::string name = model::locationName(index);
    if (spec.locationRad[static_cast<std::size_t>(index)] == 0.0 || carried.count(name)) continue;
    if (index / 3 == index % 3) {
      plan.notCarried.push_back(name +
                                ": a rotation of the line of motion about itself moves "
                                "no point (no positional effect)");
    } else {
      plan.notCarried.push_back(name + ": " + squarenessReason);
    }
  }
  for (const model::GridSpec& grid : spec.grids) {
    std::string over;
    for (Axis axis : grid.over) over += axisName(axis);
    plan.notCarried.push_back(std::string("grid E") + "XYZ"[grid.component] + " over " + over +
                              ": a map over several axes does not fit a 1-D table");
  }
}

AxisTable difference(AxisTable curve, const AxisTable& mean, int direction) {
  for (std::size_t i = 0; i < curve.errorMm.size(); ++i) curve.errorMm[i] -= mean.errorMm[i];
  curve.direction = direction;
  return curve;
}

}  // namespace

AxisGrid planGrid(const model::MachineModelSpec& spec, Axis axis, const GridSteps& steps) {
  return makeGrid(axisRange(spec, axis), steps[static_cast<std::size_t>(axis)]);
}

namespace {

/// A positioning component present in the model (EXX, EYY, EZZ) and the grid it is sampled on.
struct Positioning {
  Axis axis;
  int index;  ///< motion index
  std::string name;
  AxisGrid grid;
  bool bidirectional;
};

std::vector<Positioning> positioningComponents(const model::MachineModelSpec& spec,
                                               const GridSteps& steps) {
  std::vector<Positioning> found;
  for (Axis axis : kAxes) {
    const int index = positioningIndex(axis);
    const auto& function = spec.motion[static_cast<std::size_t>(index)];
    if (!isPresent(function)) continue;
    found.push_back({axis, index, model::motionName(index), planGrid(spec, axis, steps),
                     isBidirectional(function)});
  }
  return found;
}

/// The component alone along its own axis, for the given direction's curve.
AxisTable sampleOwnAxis(const model::MachineModelSpec& spec, const Positioning& p,
                        Direction direction) {
  return sampleTable(spec, {p.index}, {}, p.axis, p.axis, p.grid, direction);
}

}  // namespace

ExportPlan planLinuxCnc(const model::MachineModelSpec& spec, const GridSteps& steps) {
  ExportPlan plan;
  std::set<std::string> carried;
  for (const Positioning& p : positioningComponents(spec, steps)) {
    const std::string joint = p.name + " -> joint of " + axisName(p.axis);
    if (p.bidirectional) {
      plan.tables.push_back(sampleOwnAxis(spec, p, Direction::Positive));
      plan.tables.push_back(sampleOwnAxis(spec, p, Direction::Negative));
      plan.carried.push_back(joint +
                             ": forward column from values, reverse from values_negative, " +
                             gridText(p.grid));
    } else {
      plan.tables.push_back(sampleOwnAxis(spec, p, Direction::Unknown));
      plan.carried.push_back(joint + ": the same curve forward and reverse, " + gridText(p.grid));
    }
    carried.insert(p.name);
  }
  listNotCarried(spec, carried,
                 "straightness; a joint's COMP_FILE corrects that joint along itself only",
                 "squareness; a joint's COMP_FILE cannot move another joint", plan);
  return plan;
}

ExportPlan planSiemens(const model::MachineModelSpec& spec, const GridSteps& steps) {
  ExportPlan plan;
  std::set<std::string> carried;
  for (const Positioning& p : positioningComponents(spec, steps)) {
    const AxisTable mean = sampleOwnAxis(spec, p, Direction::Unknown);
    plan.tables.push_back(mean);
    const std::string axis = axisName(p.axis);
    if (p.bidirectional) {
      plan.tables.push_back(difference(sampleOwnAxis(spec, p, Direction::Positive), mean, +1));
      plan.tables.push_back(difference(sampleOwnAxis(spec, p, Direction::Negative), mean, -1));
      plan.carried.push_back(p.name + " -> LEC of " + axis +
                             " (mean of values and values_negative) plus two direction-dependent "
                             "CEC tables " +
                             axis + " -> " + axis + " (each curve minus the mean), " +
                             gridText(p.grid));
    } else {
      plan.carried.push_back(p.name + " -> LEC of " + axis + ", " + gridText(p.grid));
    }
    carried.insert(p.name);
  }
  for (Axis input : kAxes) {
    for (Axis output : kAxes) {
      if (input == output) continue;
      const int straightness = model::motionIndex(input, static_cast<model::MotionKind>(output));
      const int squareness = squarenessIndex(input, output);
      std::vector<int> motion, location;
      if (isPresent(spec.motion[static_cast<std::size_t>(straightness)])) {
        motion.push_back(straightness);
      }
      if (spec.locationRad[static_cast<std::size_t>(squareness)] != 0.0) {
        location.push_back(squareness);
      }
      if (motion.empty() && location.empty()) continue;
      const AxisGrid grid = planGrid(spec, input, steps);
      std::string names;
      for (int index : motion) names += model::motionName(index);
      for (int index : location) {
        names += (names.empty() ? "" : " + ") + model::locationName(index);
      }
      const bool bidirectional =
          !motion.empty() && isBidirectional(spec.motion[static_cast<std::size_t>(straightness)]);
      if (bidirectional) {
        plan.tables.push_back(
            sampleTable(spec, motion, location, input, output, grid, Direction::Positive));
        plan.tables.push_back(
            sampleTable(spec, motion, location, input, output, grid, Direction::Negative));
      } else {
        plan.tables.push_back(
            sampleTable(spec, motion, location, input, output, grid, Direction::Unknown));
      }
      plan.carried.push_back(
          names + " -> CEC table, input " + axisName(input) + ", output " + axisName(output) +
          (bidirectional ? " (one table per direction)" : "") + ", " + gridText(grid));
      for (int index : motion) carried.insert(model::motionName(index));
      for (int index : location) carried.insert(model::locationName(index));
    }
  }
  listNotCarried(spec, carried, "not exported", "not exported", plan);
  return plan;
}

ExportPlan planComponent(const model::MachineModelSpec& spec, const std::string& name,
                         const GridSteps& steps) {
  ExportPlan plan;
  for (int index = 0; index < 18; ++index) {
    if (model::motionName(index) != name) continue;
    const Axis input = static_cast<Axis>(index / 6);
    const int kind = index % 6;
    const AxisGrid grid = planGrid(spec, input, steps);
    if (kind < 3) {
      plan.tables.push_back(
          sampleTable(spec, {index}, {}, input, static_cast<Axis>(kind), grid, Direction::Unknown));
    }
    plan.carried.push_back(name + " along " + axisName(input) + ", " + gridText(grid));
    listNotCarried(spec, {name}, "not in this table", "not in this table", plan);
    return plan;
  }
  for (int index = 0; index < 9; ++index) {
    if (model::locationName(index) != name) continue;
    const Axis input = static_cast<Axis>(index / 3);
    const int about = index % 3;
    const AxisGrid grid = planGrid(spec, input, steps);
    if (about != static_cast<int>(input)) {
      const auto output = static_cast<Axis>(3 - static_cast<int>(input) - about);
      plan.tables.push_back(
          sampleTable(spec, {}, {index}, input, output, grid, Direction::Unknown));
    }
    plan.carried.push_back(name + " along " + axisName(input) + ", " + gridText(grid));
    listNotCarried(spec, {name}, "not in this table", "not in this table", plan);
    return plan;
  }
  throw std::invalid_argument("unknown component \"" + name +
                              "\" (expected an ISO 230-1 name such as EXX, EYX, EBX or EC0Y)");
}

}  // namespace volcomp::metrology
