#pragma once
// Hanak, Zirn and Ruoff's planar 2-DOF device: the paper's table 2 values and synthetic lattice-grid-plate
// readings, shared by the tests and the benchmark.

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "random_draws.hpp"
#include "volcomp/calibration/planar2dof.hpp"

namespace volcomp::calibration::testing {

inline constexpr double kDeg = std::numbers::pi / 180.0;

// Hanak, Zirn and Ruoff's table 2, "optimized values" (lengths mm, phi rad); eb = ehb = 0 by the paper's choice.
inline Planar2DofParameters paperOptimised() {
  return {0.30, 0.10, 1.53, 0.13, 0.0, 0.0, -0.184 * kDeg, -2.1e-3, 0.7e-3};
}
// Hanak, Zirn and Ruoff's table 2, "starting values".
inline Planar2DofParameters paperStart() {
  return {0.1, 0.1, 1.0, 0.1, 0.0, 0.0, 0.057 * kDeg, 3e-3, 3e-3};
}

// 25 points on a 40 mm x 40 mm square (Hanak, Zirn and Ruoff's fig. 5), TCP about 200 mm above the guide, LGP
// readings = R(phi) r + origin (so that g_i - g_ref = R(phi)(r_i - r_ref) + e_K, see
// planar2dof.hpp) with Gaussian noise of `noiseMm` per coordinate. The reference reading's random
// error is what (exK, eyK) stand for in the paper, so it is off by exactly -(exK, eyK) and has no
// other noise. Note that the paper's sum F = sum_i |dL_i|^2 includes the reference point, whose
// residual is (exK, eyK) itself: (exK, eyK) is one more realisation of the reading noise, estimated
// with the shrinkage of a least-squares fit (noise-free data are reproduced exactly only when it is
// zero).
inline std::vector<Planar2DofSample> simulatePlanar(const Planar2DofParameters& truth,
                                                    double noiseMm, unsigned seed) {
  const Planar2DofGeometry geometry;
  std::mt19937 generator(seed);
  std::normal_distribution<double> noise(0.0, noiseMm);
  const double c = std::cos(truth[phi]), s = std::sin(truth[phi]);
  std::vector<Planar2DofSample> samples;
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      const bool reference = row == 0 && column == 0;
      const Eigen::Vector2d tcp(-20.0 + 10.0 * column, 180.0 + 10.0 * row);
      const Eigen::Vector2d readings = planar2DofInverse(geometry, truth, tcp);
      Planar2DofSample sample;
      sample.aMm = readings.x();
      sample.bMm = readings.y();
      sample.lgpMm = Eigen::Vector2d(c * tcp.x() + s * tcp.y(), -s * tcp.x() + c * tcp.y()) +
                     Eigen::Vector2d(12.0, -7.0) +
                     (reference ? Eigen::Vector2d::Zero() : testutil::draw2(noise, generator));
      samples.push_back(sample);
    }
  }
  samples[0].lgpMm -= Eigen::Vector2d(truth[exK], truth[eyK]);
  return samples;
}

}  // namespace volcomp::calibration::testing
