#include "volcomp/metrology/remaining_error.hpp"

#include <cmath>

namespace volcomp::metrology {
namespace {

bool anyBidirectional(const model::MachineModelSpec& spec) {
  for (const auto& function : spec.motion) {
    if (isBidirectional(function)) return true;
  }
  return false;
}

struct Accumulator {
  double sumSquares = 0.0;
  double max = 0.0;
  std::size_t count = 0;
  void add(double length) {
    sumSquares += length * length;
    max = std::max(max, length);
    ++count;
  }
  ErrorStatistics statistics() const {
    return {count == 0 ? 0.0 : std::sqrt(sumSquares / static_cast<double>(count)), max};
  }
};

bool tableApplies(const AxisTable& table, const model::Directions& directions) {
  if (table.direction == 0) return true;
  return static_cast<int>(directions[static_cast<std::size_t>(table.input)]) == table.direction;
}

}  // namespace

RemainingError remainingError(const model::MachineModelSpec& spec,
                              const std::vector<AxisTable>& tables, std::size_t pointsPerAxis) {
  RemainingError result;
  std::array<std::vector<double>, 3> positions;
  for (std::size_t a = 0; a < 3; ++a) {
    result.box[a] = axisRange(spec, static_cast<model::Axis>(a));
    const double low = result.box[a].lowMm;
    const double high = result.box[a].highMm;
    const std::size_t n = high > low ? std::max<std::size_t>(pointsPerAxis, 2) : 1;
    for (std::size_t i = 0; i < n; ++i) {
      positions[a].push_back(
          n == 1 ? low : low + (high - low) * static_cast<double>(i) / static_cast<double>(n - 1));
    }
    result.pointsPerAxis[a] = n;
  }
  std::vector<model::Directions> combinations;
  if (anyBidirectional(spec)) {
    for (int bits = 0; bits < 8; ++bits) {
      model::Directions d{};
      for (std::size_t a = 0; a < 3; ++a) {
        d[a] = (bits >> a) & 1 ? model::Direction::Negative : model::Direction::Positive;
      }
      combinations.push_back(d);
    }
  } else {
    combinations.push_back(model::Directions{});
  }
  result.directionCombinations = combinations.size();

  std::vector<Eigen::Vector3d> commanded, corrected, corrections;
  std::vector<model::Directions> directions;
  for (const model::Directions& d : combinations) {
    for (double x : positions[0]) {
      for (double y : positions[1]) {
        for (double z : positions[2]) {
          const Eigen::Vector3d q(x, y, z);
          Eigen::Vector3d c = Eigen::Vector3d::Zero();
          for (const AxisTable& table : tables) {
            if (!tableApplies(table, d)) continue;
            c[static_cast<Eigen::Index>(table.output)] -=
                table.errorAt(q[static_cast<Eigen::Index>(table.input)]);
          }
          commanded.push_back(q);
          corrected.push_back(q + c);
          corrections.push_back(c);
          directions.push_back(d);
        }
      }
    }
  }
  result.evaluations = commanded.size();

  const model::MachineModel machine(spec);
  model::Workspace ws;
  std::vector<model::PointError> errors(commanded.size());
  Accumulator uncompensated, tablesOnly, live;
  model::evaluateBatch(machine, ws, commanded, errors, model::EvalMode::Exact, directions);
  for (const model::PointError& e : errors) uncompensated.add(e.errorMm.norm());
  model::evaluateBatch(machine, ws, corrected, errors, model::EvalMode::Exact, directions);
  for (std::size_t i = 0; i < errors.size(); ++i) {
    tablesOnly.add((errors[i].errorMm + corrections[i]).norm());
  }
  std::vector<model::OffsetSolution> offsets(commanded.size());
  model::solveOffsetBatch(machine, ws, commanded, offsets, directions);
  for (const model::OffsetSolution& o : offsets) {
    if (!o.converged) ++result.liveNotConverged;
    live.add(o.residualMm);
  }
  result.uncompensated = uncompensated.statistics();
  result.tablesOnly = tablesOnly.statistics();
  result.live = live.statistics();
  return result;
}

}  // namespace volcomp::metrology
