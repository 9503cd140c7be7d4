#include "volcomp/model/error_function.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "piecewise.hpp"

namespace volcomp::model {

namespace detail {

namespace {

std::string show(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

// Natural cubic spline: second derivatives M with M_0 = M_{n-1} = 0, from the tridiagonal system
// h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}), d_i the slopes.
std::vector<double> naturalSplineSecondDerivatives(std::span<const double> x,
                                                   std::span<const double> y) {
  const std::size_t n = x.size();
  std::vector<double> m(n, 0.0);
  if (n < 3) return m;
  std::vector<double> diag(n, 0.0), rhs(n, 0.0);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double h0 = x[i] - x[i - 1];
    const double h1 = x[i + 1] - x[i];
    diag[i] = 2.0 * (h0 + h1);
    rhs[i] = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
  }
  // Thomas algorithm; the system is strictly diagonally dominant, so no pivoting is needed.
  for (std::size_t i = 2; i + 1 < n; ++i) {
    const double sub = x[i] - x[i - 1];
    const double factor = sub / diag[i - 1];
    diag[i] -= factor * sub;
    rhs[i] -= factor * rhs[i - 1];
  }
  for (std::size_t i = n - 2; i >= 1; --i) {
    const double super = x[i + 1] - x[i];
    m[i] = (rhs[i] - (i + 2 < n ? super * m[i + 1] : 0.0)) / diag[i];
  }
  return m;
}

}  // namespace

bool isUniform(std::span<const double> positions) noexcept {
  const std::size_t n = positions.size();
  if (n < 2) return false;
  const double length = positions[n - 1] - positions[0];
  const double step = length / static_cast<double>(n - 1);
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double expected = positions[0] + static_cast<double>(i) * step;
    if (std::abs(positions[i] - expected) > 1e-12 * length) return false;
  }
  return true;
}

std::vector<double> buildCoefficients(std::span<const double> x, std::span<const double> y,
                                      Interpolation kind) {
  const std::size_t n = x.size();
  std::vector<double> c(4 * (n - 1), 0.0);
  // c0 = y_i and c1 = (y_{i+1} - y_i) - c2 - c3 make every interval hit both of its nodes exactly
  // (to rounding), whatever the curvature terms are.
  std::vector<double> m;
  if (kind == Interpolation::Cubic) m = naturalSplineSecondDerivatives(x, y);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double h = x[i + 1] - x[i];
    double c2 = 0.0, c3 = 0.0;
    if (kind == Interpolation::Cubic) {
      // S = a y_i + b y_{i+1} + ((a^3 - a) M_i + (b^3 - b) M_{i+1}) h^2 / 6, a = 1 - t, b = t.
      c2 = 0.5 * h * h * m[i];
      c3 = h * h / 6.0 * (m[i + 1] - m[i]);
    } else if (kind == Interpolation::Quadratic) {
      // Element e holds nodes 2e, 2e+1, 2e+2. Its Lagrange parabola in Newton form is
      // y0 + f01 (x - x0) + f012 (x - x0)(x - x1); with x = x_i + h t the t^2 coefficient is
      // f012 h^2.
      const std::size_t e0 = i - (i % 2);
      const double f01 = (y[e0 + 1] - y[e0]) / (x[e0 + 1] - x[e0]);
      const double f12 = (y[e0 + 2] - y[e0 + 1]) / (x[e0 + 2] - x[e0 + 1]);
      const double f012 = (f12 - f01) / (x[e0 + 2] - x[e0]);
      c2 = f012 * h * h;
    }
    c[4 * i + 0] = y[i];
    c[4 * i + 1] = (y[i + 1] - y[i]) - c2 - c3;
    c[4 * i + 2] = c2;
    c[4 * i + 3] = c3;
  }
  return c;
}

void validateTable(const TableSpec& table) {
  const std::size_t n = table.positionsMm.size();
  if (n == 0) throw ModelError("table: positions is empty");
  if (n < 2) throw ModelError("table: needs at least 2 positions, got 1");
  if (table.values.size() != n) {
    throw ModelError("table: values has " + std::to_string(table.values.size()) +
                     " entries but positions has " + std::to_string(n));
  }
  if (!table.valuesNegative.empty() && table.valuesNegative.size() != n) {
    throw ModelError("table: values_negative has " + std::to_string(table.valuesNegative.size()) +
                     " entries but positions has " + std::to_string(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(table.positionsMm[i])) {
      throw ModelError("table: positions[" + std::to_string(i) + "] is not a finite number");
    }
    if (!std::isfinite(table.values[i])) {
      throw ModelError("table: values[" + std::to_string(i) + "] is not a finite number");
    }
    if (!table.valuesNegative.empty() && !std::isfinite(table.valuesNegative[i])) {
      throw ModelError("table: values_negative[" + std::to_string(i) + "] is not a finite number");
    }
    if (i > 0 && !(table.positionsMm[i] > table.positionsMm[i - 1])) {
      throw ModelError("table: positions must be strictly increasing, but positions[" +
                       std::to_string(i) + "] = " + show(table.positionsMm[i]) + " follows " +
                       show(table.positionsMm[i - 1]));
    }
  }
  if (table.interpolation == Interpolation::Quadratic && (n < 3 || n % 2 == 0)) {
    throw ModelError("table: quadratic interpolation needs an odd number (>= 3) of nodes, got " +
                     std::to_string(n));
  }
}

std::array<std::vector<double>, 3> buildCurves(const TableSpec& table) {
  std::array<std::vector<double>, 3> curves;
  curves[0] = buildCoefficients(table.positionsMm, table.values, table.interpolation);
  if (table.valuesNegative.empty()) {
    curves[1] = curves[0];
    curves[2] = curves[0];
    return curves;
  }
  curves[1] = buildCoefficients(table.positionsMm, table.valuesNegative, table.interpolation);
  // Every kind is linear in the node values, so the mean curve is the table of the mean values.
  std::vector<double> mean(table.values.size());
  for (std::size_t i = 0; i < mean.size(); ++i) {
    mean[i] = 0.5 * (table.values[i] + table.valuesNegative[i]);
  }
  curves[2] = buildCoefficients(table.positionsMm, mean, table.interpolation);
  return curves;
}

}  // namespace detail

ErrorFunction::ErrorFunction(const ErrorFunctionSpec& spec) : spec_(spec) {
  if (const double* constant = std::get_if<double>(&spec)) {
    if (!std::isfinite(*constant)) throw ModelError("constant is not a finite number");
    kind_ = 0;
    constant_ = *constant;
    zero_ = constant_ == 0.0;
  } else if (const TableSpec* table = std::get_if<TableSpec>(&spec)) {
    detail::validateTable(*table);
    kind_ = 1;
    positions_ = table->positionsMm;
    curves_ = detail::buildCurves(*table);
    bidirectional_ = !table->valuesNegative.empty();
    uniform_ = detail::isUniform(positions_);
    zero_ = true;
    for (const double v : table->values) zero_ = zero_ && v == 0.0;
    for (const double v : table->valuesNegative) zero_ = zero_ && v == 0.0;
  } else {
    const PolynomialSpec& polynomial = std::get<PolynomialSpec>(spec);
    if (polynomial.coefficients.empty()) throw ModelError("polynomial: no coefficients");
    for (std::size_t i = 0; i < polynomial.coefficients.size(); ++i) {
      if (!std::isfinite(polynomial.coefficients[i])) {
        throw ModelError("polynomial: coefficient [" + std::to_string(i) +
                         "] is not a finite number");
      }
    }
    kind_ = 2;
    polynomial_ = polynomial.coefficients;
    zero_ = true;
    for (const double v : polynomial_) zero_ = zero_ && v == 0.0;
  }
}

double ErrorFunction::value(double qMm, Direction direction) const noexcept {
  switch (kind_) {
    case 0:
      return constant_;
    case 1: {
      detail::TableAxis axis = detail::makeTableAxis(positions_, uniform_);
      const int curve = bidirectional_ ? detail::curveIndex(direction) : 0;
      return detail::evaluateCubic(curves_[curve].data(), axis.locate(qMm));
    }
    default: {
      double sum = 0.0;
      for (std::size_t i = polynomial_.size(); i-- > 0;) sum = sum * qMm + polynomial_[i];
      return sum;
    }
  }
}

bool ErrorFunction::isZero() const noexcept {
  return zero_;
}
bool ErrorFunction::isBidirectional() const noexcept {
  return bidirectional_;
}

double ErrorFunction::lowerMm() const noexcept {
  return kind_ == 1 ? positions_.front() : -std::numeric_limits<double>::infinity();
}

double ErrorFunction::upperMm() const noexcept {
  return kind_ == 1 ? positions_.back() : std::numeric_limits<double>::infinity();
}

}  // namespace volcomp::model
