#include "volcomp/model/so3.hpp"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

namespace volcomp::model {
namespace {

Eigen::Matrix3d reference(double a, double b, double c) {
  return (Eigen::AngleAxisd(c, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(RotationZYX, MatchesProductOfElementaryRotationsForSmallAndLargeAngles) {
  const double angles[] = {0.0, 1e-9, -3e-6, 1e-4, -9.99e-3, 1.001e-2, 0.3, -2.0, 3.1};
  for (const double a : angles) {
    for (const double b : angles) {
      for (const double c : angles) {
        const Eigen::Matrix3d r = rotationZYX(a, b, c);
        // Both sides round (three products of entries up to 1): a few ulps of 1.
        EXPECT_LT((r - reference(a, b, c)).cwiseAbs().maxCoeff(), 1.2e-15)
            << a << " " << b << " " << c;
        EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1.2e-15);
      }
    }
  }
}

TEST(RotationZYX, SmallAngleSeriesIsExactToRounding) {
  // Near the 1e-2 switch between the series and std::sin/cos both must agree with std::sin/cos to
  // the last bit or two: Rx(a) holds cos(a) at (1,1) and sin(a) at (2,1).
  for (double a = -1e-2; a <= 1e-2; a += 1.7e-4) {
    const Eigen::Matrix3d r = rotationZYX(a, 0.0, 0.0);
    EXPECT_NEAR(r(2, 1), std::sin(a), 2e-19 + 2e-16 * std::abs(a));
    EXPECT_NEAR(r(1, 1), std::cos(a), 2.3e-16);
  }
}

TEST(RotationVector, SmallAnglesRelativeAccuracy) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  for (const double angle : {1e-12, 1e-9, 1e-6, 1e-4, 3e-3, 9e-3, 2e-2}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Eigen::Vector3d w = rotationVector(r);
    EXPECT_LT((w - angle * axis).norm(), 1e-14 * angle + 1e-22) << angle;
  }
}

TEST(RotationVector, LargeAnglesUpToPi) {
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.2, 0.9, 0.4).normalized();
  for (const double angle : {0.5, 1.5, 2.5, 3.0, std::numbers::pi - 1e-2, std::numbers::pi - 1e-4,
                             std::numbers::pi - 1e-7}) {
    const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Eigen::Vector3d w = rotationVector(r);
    EXPECT_LT((w - angle * axis).norm(), 1e-8) << angle;
    // Whatever the branch, exp(log(R)) must give R back.
    const Eigen::Matrix3d back = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    EXPECT_LT((back - r).cwiseAbs().maxCoeff(), 1e-14) << angle;
  }
  // At exactly pi the sign of the axis is arbitrary.
  const Eigen::Matrix3d half = Eigen::AngleAxisd(std::numbers::pi, axis).toRotationMatrix();
  const Eigen::Vector3d w = rotationVector(half);
  EXPECT_NEAR(w.norm(), std::numbers::pi, 1e-12);
  EXPECT_NEAR(std::abs(w.normalized().dot(axis)), 1.0, 1e-12);
}

TEST(RotationVector, IdentityIsZero) {
  EXPECT_EQ(rotationVector(Eigen::Matrix3d::Identity()), Eigen::Vector3d::Zero());
}

TEST(RotationVector, OfZYXSmallAnglesIsFirstOrderTheAngles) {
  // log(Rz(c) Ry(b) Rx(a)) = (a, b, c) + 1/2 (-b c, a c, -a b) + O(3) (BCH of the product).
  const double a = 2e-4, b = -3e-4, c = 5e-4;
  const Eigen::Vector3d w = rotationVector(rotationZYX(a, b, c));
  const Eigen::Vector3d expected(a - 0.5 * b * c, b + 0.5 * a * c, c - 0.5 * a * b);
  EXPECT_LT((w - expected).norm(), 1e-10);
}

}  // namespace
}  // namespace volcomp::model
