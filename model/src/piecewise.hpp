#pragma once
// Tables as piecewise cubics in the local coordinate t in [0, 1] of each interval
// [x_i, x_{i+1}]: value = c0 + c1 t + c2 t^2 + c3 t^3 with the four coefficients of interval i at
// coefficients[4 i .. 4 i + 3]. Linear, quadratic (3-node Lagrange elements) and natural cubic
// spline tables all take this form, so evaluation is one Horner step whatever the kind, and
// several tables over the same positions share one lookup (index i and fraction t).

#include <algorithm>
#include <span>
#include <vector>

#include "volcomp/model/error_function.hpp"

namespace volcomp::model::detail {

/// Where q falls in a table: interval index and local fraction. Held at the ends.
struct TableLocation {
  int index = 0;
  double t = 0.0;
};

/// Node positions and the constants of the O(1) uniform lookup.
struct TableAxis {
  const double* positions = nullptr;
  int count = 0;
  bool uniform = false;
  double first = 0.0;
  double last = 0.0;
  double invStep = 0.0;

  TableLocation locate(double q) const noexcept {
    if (!(q > first)) return {0, 0.0};
    if (q >= last) return {count - 2, 1.0};
    if (uniform) {
      const double s = (q - first) * invStep;
      int i = static_cast<int>(s);
      if (i > count - 2) i = count - 2;
      return {i, s - i};
    }
    const int i =
        static_cast<int>(std::upper_bound(positions, positions + count, q) - positions) - 1;
    return {i, (q - positions[i]) / (positions[i + 1] - positions[i])};
  }
};

/// True when the positions are evenly spaced to within 1e-12 of the table length, so that the
/// uniform lookup gives the same interval and fraction as the search (to rounding).
bool isUniform(std::span<const double> positions) noexcept;

/// TableAxis over `positions` (which must outlive it), `uniform` as found by isUniform.
inline TableAxis makeTableAxis(std::span<const double> positions, bool uniform) noexcept {
  TableAxis axis;
  axis.positions = positions.data();
  axis.count = static_cast<int>(positions.size());
  axis.first = positions.front();
  axis.last = positions.back();
  axis.uniform = uniform;
  axis.invStep = static_cast<double>(positions.size() - 1) / (axis.last - axis.first);
  return axis;
}

/// The 4 (n - 1) coefficients of one curve. Positions strictly increasing, n >= 2 (odd and >= 3
/// for quadratic); validated by the caller.
std::vector<double> buildCoefficients(std::span<const double> positions,
                                      std::span<const double> values, Interpolation kind);

inline double evaluateCubic(const double* coefficients, TableLocation at) noexcept {
  const double* c = coefficients + 4 * at.index;
  return c[0] + at.t * (c[1] + at.t * (c[2] + at.t * c[3]));
}

/// Validates a table spec; throws ModelError saying what is wrong.
void validateTable(const TableSpec& table);

/// The three curves of a table (positive, negative, mean), each 4 (n - 1) coefficients; for a
/// one-directional table all three equal the `values` curve.
std::array<std::vector<double>, 3> buildCurves(const TableSpec& table);

/// Curve index for a direction: 0 Positive, 1 Negative, 2 Unknown (mean).
inline int curveIndex(Direction direction) noexcept {
  static constexpr int kIndex[3] = {1, 2, 0};  // Negative, Unknown, Positive
  const unsigned slot = static_cast<unsigned>(static_cast<int>(direction) + 1);
  return slot < 3 ? kIndex[slot] : 2;  // a value outside the enum counts as Unknown
}

}  // namespace volcomp::model::detail
