#include "volcomp/model/error_function.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "piecewise.hpp"

namespace volcomp::model {
namespace {

TableSpec table(std::vector<double> x, std::vector<double> y, Interpolation kind) {
  TableSpec t;
  t.positionsMm = std::move(x);
  t.values = std::move(y);
  t.interpolation = kind;
  return t;
}

TEST(ErrorFunction, ZeroAndConstant) {
  const ErrorFunction zero;
  EXPECT_TRUE(zero.isZero());
  EXPECT_EQ(zero.value(123.0), 0.0);
  const ErrorFunction c(ErrorFunctionSpec{2.5e-3});
  EXPECT_FALSE(c.isZero());
  EXPECT_EQ(c.value(-1e6), 2.5e-3);
  EXPECT_EQ(c.value(1e6, Direction::Negative), 2.5e-3);
  EXPECT_EQ(c.lowerMm(), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.upperMm(), std::numeric_limits<double>::infinity());
}

TEST(ErrorFunction, LinearHandValuesAndClamping) {
  // Spec example 3's table (0,0)(100,5)(200,10)(300,20): at 250 halfway between 10 and 20 = 15;
  // at 50 halfway between 0 and 5 = 2.5; at 130: 5 + 0.3 * 5 = 6.5; held outside: 0 and 20.
  const ErrorFunction f(table({0, 100, 200, 300}, {0, 5, 10, 20}, Interpolation::Linear));
  EXPECT_DOUBLE_EQ(f.value(250), 15.0);
  EXPECT_DOUBLE_EQ(f.value(50), 2.5);
  EXPECT_DOUBLE_EQ(f.value(130), 6.5);
  EXPECT_DOUBLE_EQ(f.value(200), 10.0);
  EXPECT_EQ(f.value(0), 0.0);
  EXPECT_EQ(f.value(300), 20.0);
  EXPECT_EQ(f.value(-50), 0.0);
  EXPECT_EQ(f.value(1e9), 20.0);
  EXPECT_EQ(f.lowerMm(), 0.0);
  EXPECT_EQ(f.upperMm(), 300.0);
}

TEST(ErrorFunction, LinearNonUniformHandValues) {
  // Nodes 0, 10, 40 with values 1, 3, -3: at 25 (halfway in [10, 40]) 0; at 4: 1 + 0.4 * 2 = 1.8.
  const ErrorFunction f(table({0, 10, 40}, {1, 3, -3}, Interpolation::Linear));
  EXPECT_NEAR(f.value(25), 0.0, 1e-15);
  EXPECT_NEAR(f.value(4), 1.8, 1e-15);
}

TEST(ErrorFunction, QuadraticElementsHandValues) {
  // Elements (0,1,2) and (2,3,4). Element 1 values 0, 1, 4 are x^2: at 0.5 -> 0.25, 1.5 -> 2.25.
  // Element 2 values 4, 5, 8: divided differences f01 = 1, f12 = 3, f012 = (3 - 1) / 2 = 1, so
  // p(x) = 4 + (x - 2) + (x - 2)(x - 3): p(2.5) = 4.5 - 0.25 = 4.25, p(3.5) = 5.5 + 0.75 = 6.25.
  // (One parabola through all five nodes would not fit both: the elements are independent.)
  const ErrorFunction f(table({0, 1, 2, 3, 4}, {0, 1, 4, 5, 8}, Interpolation::Quadratic));
  EXPECT_NEAR(f.value(0.5), 0.25, 1e-15);
  EXPECT_NEAR(f.value(1.5), 2.25, 1e-15);
  EXPECT_NEAR(f.value(2.5), 4.25, 1e-14);
  EXPECT_NEAR(f.value(3.5), 6.25, 1e-14);
  const double nodes[] = {0, 1, 4, 5, 8};
  for (int i = 0; i <= 4; ++i) EXPECT_NEAR(f.value(i), nodes[i], 1e-15);
  EXPECT_EQ(f.value(-1), 0.0);
  EXPECT_NEAR(f.value(5), 8.0, 1e-15);
}

TEST(ErrorFunction, QuadraticNonUniformReproducesParabola) {
  // Any parabola is reproduced exactly by a 3-node Lagrange element, whatever the node spacing:
  // y = 2 - x + 0.5 x^2 on nodes 0, 1, 3 (one element).
  auto y = [](double x) { return 2 - x + 0.5 * x * x; };
  const ErrorFunction f(table({0, 1, 3}, {y(0), y(1), y(3)}, Interpolation::Quadratic));
  for (double x = 0; x <= 3; x += 0.125) EXPECT_NEAR(f.value(x), y(x), 1e-14) << x;
}

TEST(ErrorFunction, NaturalCubicSplineHandValues) {
  // Nodes 0, 1, 2, 3 with values 0, 1, 0, 1 (h = 1). Natural: M0 = M3 = 0 and
  //   4 M1 + M2 = 6 ((0 - 1) - (1 - 0)) = -12,  M1 + 4 M2 = 6 ((1 - 0) - (0 - 1)) = 12
  // so M1 = -4, M2 = 4. S = a y_i + b y_{i+1} + ((a^3 - a) M_i + (b^3 - b) M_{i+1}) / 6; at a
  // midpoint a = b = 1/2 and a^3 - a = -3/8:
  //   S(0.5) = 0.5 + (-3/8)(-4)/6 = 0.75, S(1.5) = 0.5 + (-3/8)(-4 + 4)/6 = 0.5,
  //   S(2.5) = 0.5 + (-3/8)(4)/6 = 0.25.
  const ErrorFunction f(table({0, 1, 2, 3}, {0, 1, 0, 1}, Interpolation::Cubic));
  EXPECT_NEAR(f.value(0.5), 0.75, 1e-15);
  EXPECT_NEAR(f.value(1.5), 0.5, 1e-15);
  EXPECT_NEAR(f.value(2.5), 0.25, 1e-15);
  EXPECT_NEAR(f.value(1.0), 1.0, 1e-15);
  EXPECT_EQ(f.value(-2), 0.0);
  EXPECT_NEAR(f.value(4), 1.0, 1e-15);
  // Natural end condition: second difference ~ 0 at the ends.
  const double h = 1e-4;
  EXPECT_NEAR((f.value(2 * h) - 2 * f.value(h) + f.value(0)) / (h * h), 0.0, 1e-3);
}

TEST(ErrorFunction, CubicSplineNonUniformHandValue) {
  // Nodes 0, 1, 3 values 0, 2, 0: h0 = 1, h1 = 2; 2 (h0 + h1) M1 = 6 ((0 - 2)/2 - (2 - 0)/1)
  // -> 6 M1 = -18, M1 = -3. On [1, 3] at x = 2 (t = 1/2, h = 2):
  // S = 0.5 * 2 + 0.5 * 0 + ((-3/8)(-3) + (-3/8) * 0) * 4 / 6 = 1 + 0.75 = 1.75.
  const ErrorFunction f(table({0, 1, 3}, {0, 2, 0}, Interpolation::Cubic));
  EXPECT_NEAR(f.value(2), 1.75, 1e-15);
  // On [0, 1] at 0.5: 0.5 * 2 + (-3/8)(-3) / 6 = 1 + 0.1875.
  EXPECT_NEAR(f.value(0.5), 1.1875, 1e-15);
}

TEST(ErrorFunction, CubicReproducesLinearData) {
  const ErrorFunction f(table({-5, 0, 5, 10, 20}, {-1, 0, 1, 2, 4}, Interpolation::Cubic));
  for (double x = -5; x <= 20; x += 0.7) EXPECT_NEAR(f.value(x), x / 5, 1e-14) << x;
}

TEST(ErrorFunction, BidirectionalCurves) {
  // Positive curve 0, 10, 20; negative 4, 6, 8 (mean 2, 8, 14). At x = 50 (halfway in the first
  // interval): positive 5, negative 5, mean 5; at x = 150: positive 15, negative 7, mean 11.
  TableSpec t = table({0, 100, 200}, {0, 10, 20}, Interpolation::Linear);
  t.valuesNegative = {4, 6, 8};
  const ErrorFunction f(t);
  EXPECT_TRUE(f.isBidirectional());
  EXPECT_DOUBLE_EQ(f.value(150, Direction::Positive), 15.0);
  EXPECT_DOUBLE_EQ(f.value(150, Direction::Negative), 7.0);
  EXPECT_DOUBLE_EQ(f.value(150, Direction::Unknown), 11.0);
  EXPECT_DOUBLE_EQ(f.value(150), 11.0);
  EXPECT_DOUBLE_EQ(f.value(50, Direction::Negative), 5.0);
  // Held outside, per curve.
  EXPECT_EQ(f.value(-10, Direction::Negative), 4.0);
  EXPECT_EQ(f.value(300, Direction::Positive), 20.0);
  EXPECT_EQ(f.value(300, Direction::Unknown), 14.0);
  // A one-directional table ignores the direction.
  const ErrorFunction single(table({0, 100, 200}, {0, 10, 20}, Interpolation::Linear));
  EXPECT_FALSE(single.isBidirectional());
  EXPECT_EQ(single.value(150, Direction::Negative), single.value(150, Direction::Positive));
}

TEST(ErrorFunction, BidirectionalCubicMeanIsMeanOfCurves) {
  TableSpec t = table({0, 1, 2, 3, 4}, {0, 1, 0, 1, 3}, Interpolation::Cubic);
  t.valuesNegative = {1, 1, 2, 0, -1};
  const ErrorFunction f(t);
  for (double x = -0.5; x <= 4.5; x += 0.3) {
    EXPECT_NEAR(f.value(x, Direction::Unknown),
                0.5 * (f.value(x, Direction::Positive) + f.value(x, Direction::Negative)), 1e-14);
  }
}

TEST(ErrorFunction, UniformLookupEqualsSearch) {
  // The O(1) lookup of a uniform table and the binary search must pick the same interval and
  // fraction (to rounding) everywhere, including at nodes and beyond the ends.
  std::vector<double> x;
  for (int i = 0; i <= 100; ++i) x.push_back(-250.0 + 8.5 * i);
  ASSERT_TRUE(detail::isUniform(x));
  const detail::TableAxis fast = detail::makeTableAxis(x, true);
  const detail::TableAxis search = detail::makeTableAxis(x, false);
  std::vector<double> y;
  for (std::size_t i = 0; i < x.size(); ++i) y.push_back(std::sin(0.1 * static_cast<double>(i)));
  for (const Interpolation kind :
       {Interpolation::Linear, Interpolation::Quadratic, Interpolation::Cubic}) {
    const std::vector<double> c = detail::buildCoefficients(x, y, kind);
    for (double q = -300; q <= 650; q += 0.37) {
      const detail::TableLocation a = fast.locate(q), b = search.locate(q);
      const double va = detail::evaluateCubic(c.data(), a);
      const double vb = detail::evaluateCubic(c.data(), b);
      EXPECT_NEAR(va, vb, 1e-13) << q;
    }
    for (const double node : x) {
      EXPECT_NEAR(detail::evaluateCubic(c.data(), fast.locate(node)),
                  detail::evaluateCubic(c.data(), search.locate(node)), 1e-13);
    }
  }
}

TEST(ErrorFunction, UniformAndNonUniformTablesGiveSameValues) {
  // A linear table with an extra node inserted on the line is the same function, but is not
  // uniform any more (so it takes the search path).
  const ErrorFunction uniform(
      table({0, 10, 20, 30, 40}, {1.0, -2.0, 0.5, 4.0, 3.0}, Interpolation::Linear));
  const ErrorFunction searched(
      table({0, 10, 15, 20, 30, 40}, {1.0, -2.0, -0.75, 0.5, 4.0, 3.0}, Interpolation::Linear));
  for (double q = -5; q <= 45; q += 0.113) {
    EXPECT_NEAR(uniform.value(q), searched.value(q), 1e-14) << q;
  }
}

TEST(ErrorFunction, UniformDetection) {
  EXPECT_TRUE(detail::isUniform(std::vector<double>{0, 0.1, 0.2, 0.30000000000000004, 0.4}));
  EXPECT_TRUE(detail::isUniform(std::vector<double>{-5, 5}));
  EXPECT_FALSE(detail::isUniform(std::vector<double>{0, 1, 2.001, 3}));
}

TEST(ErrorFunction, Polynomial) {
  // 1 + 2 q + 3 q^2: at 2 -> 1 + 4 + 12 = 17; at -1 -> 1 - 2 + 3 = 2; no clamping of its own.
  const ErrorFunction f(PolynomialSpec{{1, 2, 3}});
  EXPECT_DOUBLE_EQ(f.value(2), 17.0);
  EXPECT_DOUBLE_EQ(f.value(-1), 2.0);
  EXPECT_DOUBLE_EQ(f.value(1000), 3002001.0);
  EXPECT_FALSE(f.isZero());
  EXPECT_TRUE(ErrorFunction(PolynomialSpec{{0, 0}}).isZero());
}

TEST(ErrorFunction, RejectsBadTables) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto bad = [](const ErrorFunctionSpec& spec) { EXPECT_THROW(ErrorFunction{spec}, ModelError); };
  bad(table({}, {}, Interpolation::Linear));
  bad(table({1}, {1}, Interpolation::Linear));
  bad(table({0, 1, 1}, {0, 0, 0}, Interpolation::Linear));
  bad(table({0, 2, 1}, {0, 0, 0}, Interpolation::Linear));
  bad(table({0, 1, 2}, {0, 0}, Interpolation::Linear));
  bad(table({0, 1, 2, 3}, {0, 0, 0, 0}, Interpolation::Quadratic));
  bad(table({0, 1}, {0, 0}, Interpolation::Quadratic));
  bad(table({0, nan, 2}, {0, 0, 0}, Interpolation::Linear));
  bad(table({0, 1, 2}, {0, inf, 0}, Interpolation::Cubic));
  TableSpec negative = table({0, 1, 2}, {0, 0, 0}, Interpolation::Linear);
  negative.valuesNegative = {0, 0};
  bad(negative);
  negative.valuesNegative = {0, nan, 0};
  bad(negative);
  bad(PolynomialSpec{{}});
  bad(PolynomialSpec{{1, nan}});
  bad(ErrorFunctionSpec{inf});
  try {
    ErrorFunction f(table({0, 2, 1}, {0, 0, 0}, Interpolation::Linear));
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("positions[2]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace volcomp::model
