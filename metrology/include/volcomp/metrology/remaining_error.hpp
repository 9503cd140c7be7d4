#pragma once
/// The error the model predicts over the travel (a) uncompensated, (b) when only a set of
/// controller tables is applied, (c) with volcomp's live compensation, as RMS and maximum of the
/// position error's length |p - p0| (mm).
///
/// Grid: `pointsPerAxis` evenly spaced positions over each axis' range (its travel, else its
/// tables' range; an axis with neither stays at 0). When the model has bidirectional tables every
/// point is evaluated for all 8 combinations of axis directions, else with unknown directions.
/// (b) applies the tables as the controllers do, looked up at the commanded position: the
/// commanded point q becomes q + c with c_L = -Σ e(q_input) over the tables whose output is L
/// (direction-dependent tables only in their direction), and what is left is
/// p(q + c) - p0(q) = E(q + c) + c. (c) is the residual of the live offset solve
/// (solveOffsetBatch), p(q + o) - p0(q). Both (a) and (b) go through evaluateBatch.

#include <array>
#include <cstddef>
#include <vector>

#include "volcomp/metrology/axis_tables.hpp"

namespace volcomp::metrology {

struct ErrorStatistics {
  double rmsMm = 0.0;
  double maxMm = 0.0;
};

struct RemainingError {
  std::array<AxisRange, 3> box{};
  std::array<std::size_t, 3> pointsPerAxis{};
  std::size_t directionCombinations = 1;
  /// Evaluations per statistic: product of pointsPerAxis times directionCombinations.
  std::size_t evaluations = 0;
  ErrorStatistics uncompensated, tablesOnly, live;
  /// Points where the live offset solve did not converge (counted in `live` as they are).
  std::size_t liveNotConverged = 0;
};

RemainingError remainingError(const model::MachineModelSpec& spec,
                              const std::vector<AxisTable>& tables, std::size_t pointsPerAxis);

}  // namespace volcomp::metrology
