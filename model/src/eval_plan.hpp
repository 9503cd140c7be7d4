#pragma once
// Flattened, immutable evaluation data of a MachineModel, laid out for the per-point hot path:
// per axis the travel limits, the constant components, and the tables grouped by their node
// positions so that one lookup (interval index and fraction) serves every table of the group.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::model::detail {

struct EvalPlan {
  /// One table component: its slot (0..5, the MotionKind) in the axis' block of six, and the
  /// offsets in `data` of its three curves' coefficients (Positive, Negative, Unknown).
  struct Entry {
    int slot = 0;
    std::array<int, 3> curve{};
  };
  /// Tables of one axis sharing the same node positions (stored at `positions` in `data`).
  struct Group {
    int count = 0;
    bool uniform = false;
    double first = 0.0, last = 0.0, invStep = 0.0;
    int positions = 0;
    int entryBegin = 0, entryEnd = 0;
  };
  struct Polynomial {
    int slot = 0;
    int begin = 0, end = 0;  // coefficients in `data`, c0 first
  };
  struct AxisPlan {
    double lowerMm = 0.0, upperMm = 0.0;  // travel, +-inf when unbounded
    std::array<double, 6> constants{};    // constant components (0 where a table/polynomial is)
    int groupBegin = 0, groupEnd = 0;
    int polynomialBegin = 0, polynomialEnd = 0;
    double sign = 1.0;  // +1 tool side, -1 workpiece side
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    Eigen::Vector3d directionMinusUnit = Eigen::Vector3d::Zero();  // d_K - e_K, full precision
  };

  std::array<AxisPlan, 3> axes;
  std::vector<double> data;
  std::vector<Group> groups;
  std::vector<Entry> entries;
  std::vector<Polynomial> polynomials;
  /// Tool-side axes from the frame outward, then workpiece-side axes from the frame outward.
  std::array<int, 3> toolChain{};
  int toolCount = 0;
  std::array<int, 3> workpieceChain{};
  int workpieceCount = 0;
};

struct PlanAccess {
  static const EvalPlan& plan(const MachineModel& model) noexcept { return *model.plan_; }
};

}  // namespace volcomp::model::detail
