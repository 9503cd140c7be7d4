#pragma once
/// Grid maps (docs/model-file.md "Grid maps"): a translational error component (EX, EY or EZ, mm)
/// over 2 or 3 axes, bi- or trilinearly interpolated, positions clamped to the grid.

#include <array>
#include <vector>

#include "volcomp/model/types.hpp"

namespace volcomp::model {

struct GridSpec {
  /// 0, 1, 2 for EX, EY, EZ: which component of the position error the grid adds to.
  int component = 2;
  /// The axes the grid is over, in the order `values` is indexed (2 or 3 distinct axes).
  std::vector<Axis> over;
  /// Strictly increasing node positions (mm) per axis of `over` (each at least 2 nodes).
  std::vector<std::vector<double>> axesMm;
  /// Values in mm, flattened row-major in the order of `over`: for 2 axes index i * n1 + j,
  /// for 3 axes (i * n1 + j) * n2 + k.
  std::vector<double> valuesMm;
};

class Grid {
 public:
  /// Throws ModelError on inconsistent data.
  explicit Grid(GridSpec spec);
  /// Interpolated value (mm) at the commanded position q (mm); positions are clamped to the grid.
  double valueMm(const double* qMm) const noexcept;
  int component() const noexcept { return spec_.component; }
  const GridSpec& spec() const noexcept { return spec_; }

 private:
  GridSpec spec_;
  std::array<bool, 3> uniform_{};  // per axis of `over`: evenly spaced nodes, O(1) lookup
};

}  // namespace volcomp::model
