#include "volcomp/model/grid.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace volcomp::model {
namespace {

// 2-D grid over (X, Y): X nodes 0, 100, 300 (non-uniform), Y nodes -50, 50; values[i][j]:
//   X=0:   1,  3
//   X=100: 5,  9
//   X=300: -2, 0
GridSpec flatSpec() {
  GridSpec spec;
  spec.component = 2;
  spec.over = {Axis::X, Axis::Y};
  spec.axesMm = {{0, 100, 300}, {-50, 50}};
  spec.valuesMm = {1, 3, 5, 9, -2, 0};
  return spec;
}

TEST(Grid, BilinearCornersAndCellCentres) {
  const Grid grid(flatSpec());
  EXPECT_EQ(grid.component(), 2);
  const double corners[3][2] = {{1, 3}, {5, 9}, {-2, 0}};
  const double xs[3] = {0, 100, 300}, ys[2] = {-50, 50};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 2; ++j) {
      const double q[3] = {xs[i], ys[j], 123.0};
      EXPECT_NEAR(grid.valueMm(q), corners[i][j], 1e-15);
    }
  }
  // Cell centres are the mean of the four corners: (1 + 3 + 5 + 9) / 4 = 4.5 at (50, 0),
  // (5 + 9 - 2 + 0) / 4 = 3 at (200, 0).
  const double c1[3] = {50, 0, 0}, c2[3] = {200, 0, -999};
  EXPECT_NEAR(grid.valueMm(c1), 4.5, 1e-15);
  EXPECT_NEAR(grid.valueMm(c2), 3.0, 1e-15);
  // On an edge the value is linear: at (100, 0) halfway between 5 and 9 = 7.
  const double edge[3] = {100, 0, 0};
  EXPECT_NEAR(grid.valueMm(edge), 7.0, 1e-15);
  // At (25, 25): t = 0.25, u = 0.75: 0.75 (0.25 * 1 + 0.75 * 3) + 0.25 (0.25 * 5 + 0.75 * 9)
  // = 0.75 * 2.5 + 0.25 * 8 = 3.875.
  const double inside[3] = {25, 25, 0};
  EXPECT_NEAR(grid.valueMm(inside), 3.875, 1e-15);
}

TEST(Grid, BilinearClamped) {
  const Grid grid(flatSpec());
  // Beyond X = 300 and below Y = -50: the corner value -2. Beyond X only, at Y = 0: -1.
  const double far[3] = {1000, -1000, 0}, side[3] = {400, 0, 0}, before[3] = {-10, 50, 0};
  EXPECT_EQ(grid.valueMm(far), -2.0);
  EXPECT_NEAR(grid.valueMm(side), -1.0, 1e-15);
  EXPECT_EQ(grid.valueMm(before), 3.0);
}

// f(x, y, z) = 1 + 2x + 3y + 4z + 0.5 xy - 0.25 yz + 0.125 xyz is linear in each variable
// separately, so trilinear interpolation on any box grid reproduces it exactly.
double multilinear(double x, double y, double z) {
  return 1 + 2 * x + 3 * y + 4 * z + 0.5 * x * y - 0.25 * y * z + 0.125 * x * y * z;
}

// Over (Z, X, Y) so that the index order differs from the axis order.
GridSpec volumeSpec() {
  GridSpec spec;
  spec.component = 0;
  spec.over = {Axis::Z, Axis::X, Axis::Y};
  spec.axesMm = {{-2, 0, 1}, {0, 1, 2, 3}, {5, 7}};
  for (const double z : spec.axesMm[0]) {
    for (const double x : spec.axesMm[1]) {
      for (const double y : spec.axesMm[2]) spec.valuesMm.push_back(multilinear(x, y, z));
    }
  }
  return spec;
}

TEST(Grid, TrilinearCornersCentresAndInterior) {
  const Grid grid(volumeSpec());
  const GridSpec& spec = grid.spec();
  for (const double z : spec.axesMm[0]) {
    for (const double x : spec.axesMm[1]) {
      for (const double y : spec.axesMm[2]) {
        const double q[3] = {x, y, z};
        EXPECT_NEAR(grid.valueMm(q), multilinear(x, y, z), 1e-13);
      }
    }
  }
  // Cell centre of the cell z in [0, 1], x in [1, 2], y in [5, 7]: the mean of its 8 corners.
  double mean = 0;
  for (const double z : {0.0, 1.0}) {
    for (const double x : {1.0, 2.0}) {
      for (const double y : {5.0, 7.0}) mean += multilinear(x, y, z) / 8;
    }
  }
  const double centre[3] = {1.5, 6.0, 0.5};
  EXPECT_NEAR(grid.valueMm(centre), mean, 1e-13);
  for (double x = 0; x <= 3; x += 0.37) {
    for (double y = 5; y <= 7; y += 0.29) {
      for (double z = -2; z <= 1; z += 0.31) {
        const double q[3] = {x, y, z};
        EXPECT_NEAR(grid.valueMm(q), multilinear(x, y, z), 1e-12);
      }
    }
  }
}

TEST(Grid, TrilinearClamped) {
  const Grid grid(volumeSpec());
  // Each coordinate is clamped to its axis range before interpolating.
  const double q[3] = {10, 0, -7};
  EXPECT_NEAR(grid.valueMm(q), multilinear(3, 5, -2), 1e-13);
  const double r[3] = {-1, 6, 0.5};
  EXPECT_NEAR(grid.valueMm(r), multilinear(0, 6, 0.5), 1e-13);
}

TEST(Grid, RejectsBadData) {
  auto bad = [](GridSpec spec) { EXPECT_THROW(Grid{std::move(spec)}, ModelError); };
  GridSpec s = flatSpec();
  s.component = 3;
  bad(s);
  s = flatSpec();
  s.over = {Axis::X};
  s.axesMm = {{0, 1}};
  bad(s);
  s = flatSpec();
  s.over = {Axis::X, Axis::X};
  bad(s);
  s = flatSpec();
  s.axesMm[0] = {0, 100, 100};
  bad(s);
  s = flatSpec();
  s.axesMm[1] = {0};
  s.valuesMm = {1, 2, 3};
  bad(s);
  s = flatSpec();
  s.valuesMm.pop_back();
  bad(s);
  s = flatSpec();
  s.valuesMm[2] = std::numeric_limits<double>::quiet_NaN();
  bad(s);
  s = flatSpec();
  s.axesMm.pop_back();
  bad(s);
}

}  // namespace
}  // namespace volcomp::model
