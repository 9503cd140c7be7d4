#pragma once
/// Error functions along one axis (docs/model-file.md "Error functions"): constant, table (linear,
/// quadratic 3-node elements, natural cubic spline; optionally bidirectional), polynomial. Values
/// are in the model's internal units (mm or rad); positions are mm.

#include <array>
#include <variant>
#include <vector>

#include "volcomp/model/types.hpp"

namespace volcomp::model {

enum class Interpolation : std::uint8_t { Linear, Quadratic, Cubic };

/// A measured table. `positionsMm` strictly increasing; `values` the same length (the positive-
/// direction curve when `valuesNegative` is not empty); `valuesNegative` empty or the same length.
/// Quadratic needs an odd number (>= 3) of nodes: elements are nodes 0-1-2, 2-3-4, ...
struct TableSpec {
  std::vector<double> positionsMm;
  std::vector<double> values;
  std::vector<double> valuesNegative;
  Interpolation interpolation = Interpolation::Linear;
};

/// c0 + c1 q + c2 q^2 + ..., q in mm.
struct PolynomialSpec {
  std::vector<double> coefficients;
};

/// What a file says about one motion-error component. A plain double is a constant.
using ErrorFunctionSpec = std::variant<double, TableSpec, PolynomialSpec>;

/// Immutable, evaluable error function. Construction validates and precomputes (spline second
/// derivatives, the mean curve, uniform spacing for O(1) lookup); evaluation never allocates.
/// Outside a table the value is held at the nearest end (no extrapolation).
class ErrorFunction {
 public:
  /// The zero function.
  ErrorFunction() = default;
  /// Throws ModelError when the spec is inconsistent (non-increasing positions, length mismatch,
  /// even node count for quadratic, non-finite numbers, empty table or polynomial).
  explicit ErrorFunction(const ErrorFunctionSpec& spec);

  /// Value at q (mm) for the given direction of travel: Positive uses `values`, Negative uses
  /// `valuesNegative`, Unknown the mean of both. Without `valuesNegative` the direction is ignored.
  double value(double qMm, Direction direction = Direction::Unknown) const noexcept;

  bool isZero() const noexcept;
  bool isBidirectional() const noexcept;
  /// Range of table positions (or +-inf for constants and polynomials).
  double lowerMm() const noexcept;
  double upperMm() const noexcept;
  /// The spec it was built from (for `volcomp check` and for writing models back out).
  const ErrorFunctionSpec& spec() const noexcept { return spec_; }

 private:
  ErrorFunctionSpec spec_{0.0};
  int kind_ = 0;  // 0 constant, 1 table, 2 polynomial
  double constant_ = 0.0;
  std::vector<double> polynomial_;
  // Table data (used when kind_ == 1): positions and three curves (positive, negative, mean),
  // each stored as per-interval cubic coefficients in the interval's local coordinate (see
  // model/src/piecewise.hpp), so that every interpolation kind evaluates in one Horner step.
  std::vector<double> positions_;
  std::array<std::vector<double>, 3> curves_;
  bool bidirectional_ = false;
  bool uniform_ = false;
  bool zero_ = true;
};

}  // namespace volcomp::model
