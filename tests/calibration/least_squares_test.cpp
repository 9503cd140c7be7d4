// The rank policy, covariance and null-space naming of analyse() on hand-made Jacobians.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <map>
#include <random>

#include "synthetic.hpp"
#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {
namespace {

using testing::randomMatrix;

TEST(Analyse, FullRankCovarianceIsTheTextbookFormula) {
  // Columns of very different scales (as mm, rad and mm/mm^2 parameters have): the scaling must
  // not change the covariance, which is s0^2 (J^T J)^-1 with s0^2 = |r|^2 / (m - n).
  Eigen::MatrixXd jacobian = randomMatrix(40, 4, 1);
  jacobian.col(1) *= 1e4;
  jacobian.col(3) *= 1e-5;
  const Eigen::VectorXd residuals = randomMatrix(40, 1, 2).col(0) * 0.01;
  const FitStatistics stats = analyse(jacobian, residuals, {"a", "b", "c", "d"}, 1e-7);
  EXPECT_EQ(stats.rank, 4);
  EXPECT_EQ(stats.dof, 36);
  EXPECT_TRUE(stats.unidentifiable.empty());
  const double s0squared = residuals.squaredNorm() / 36.0;
  EXPECT_NEAR(stats.varianceFactor, s0squared, 1e-15);
  const Eigen::MatrixXd expected =
      s0squared * (jacobian.transpose() * jacobian).ldlt().solve(Eigen::MatrixXd::Identity(4, 4));
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      EXPECT_NEAR(stats.covariance(i, j), expected(i, j),
                  1e-9 * std::sqrt(expected(i, i) * expected(j, j)));
    }
    EXPECT_NEAR(stats.correlation(i, i), 1.0, 1e-15);
  }
}

TEST(Analyse, DependentColumnsAreNamedWithTheirCoefficients) {
  // Column d = 2 b - c: rank 3, one combination {b, c, d}. The reported coefficients are in
  // scaled units (they depend on the column norms), so the names and the signs are checked:
  // J (db, dc, dd) = db b + dc c + dd (2 b - c) vanishes for db = -2 dd, dc = dd, so b and d have
  // opposite signs and c and d the same sign.
  Eigen::MatrixXd jacobian = randomMatrix(30, 4, 3);
  jacobian.col(3) = 2.0 * jacobian.col(1) - jacobian.col(2);
  const FitStatistics stats =
      analyse(jacobian, Eigen::VectorXd::Zero(30), {"a", "b", "c", "d"}, 1e-7);
  EXPECT_EQ(stats.rank, 3);
  ASSERT_EQ(stats.unidentifiable.size(), 1u);
  const Combination& combination = stats.unidentifiable[0];
  ASSERT_EQ(combination.terms.size(), 3u);
  std::map<int, double> coefficient(combination.terms.begin(), combination.terms.end());
  ASSERT_EQ(coefficient.count(0), 0u);
  EXPECT_LT(coefficient[1] * coefficient[3], 0.0);
  EXPECT_GT(coefficient[2] * coefficient[3], 0.0);
  EXPECT_LT(combination.relativeSingularValue, 1e-12);
  EXPECT_EQ(combination.description.rfind("b, c and d are not separable", 0), 0u)
      << combination.description;
  EXPECT_TRUE(stats.identifiable[0]);
  EXPECT_FALSE(stats.identifiable[3]);
  EXPECT_TRUE(std::isinf(stats.fullConditionNumber) || stats.fullConditionNumber > 1e12);
}

TEST(Analyse, ParameterWithoutEffectIsNamedAlone) {
  Eigen::MatrixXd jacobian = randomMatrix(20, 3, 4);
  jacobian.col(1).setZero();
  const FitStatistics stats =
      analyse(jacobian, Eigen::VectorXd::Zero(20), {"EXX", "EAZ", "EBX"}, 1e-7);
  EXPECT_EQ(stats.rank, 2);
  ASSERT_EQ(stats.unidentifiable.size(), 1u);
  EXPECT_EQ(stats.unidentifiable[0].description.rfind("EAZ has no effect on the measured data", 0),
            0u)
      << stats.unidentifiable[0].description;
}

TEST(Analyse, RankToleranceIsTheDecision) {
  // Column c = a + 1e-5 * noise: relative singular value about 1e-5 / sqrt(2) after scaling.
  Eigen::MatrixXd jacobian = randomMatrix(50, 3, 5);
  jacobian.col(2) = jacobian.col(0) + 1e-5 * randomMatrix(50, 1, 6).col(0);
  EXPECT_EQ(analyse(jacobian, Eigen::VectorXd::Zero(50), {"a", "b", "c"}, 1e-7).rank, 3);
  EXPECT_EQ(analyse(jacobian, Eigen::VectorXd::Zero(50), {"a", "b", "c"}, 1e-3).rank, 2);
}

}  // namespace
}  // namespace volcomp::calibration
