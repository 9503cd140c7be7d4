#pragma once
/// Vectors of random draws in a fixed order, the same whatever the compiler.
///
/// The arguments of a constructor call are evaluated in an unspecified order: g++ evaluates
/// `Eigen::Vector3d(d(g), d(g), d(g))` last to first, clang first to last, so the same seed gave
/// each compiler other synthetic data (and a test written against one could fail with the
/// other). These draw z (or y) first, then back to x: g++'s order, which the tests' expected
/// figures were written against.

#include <Eigen/Core>

namespace volcomp::testutil {

template <class Distribution, class Generator>
Eigen::Vector3d draw3(Distribution& distribution, Generator& generator) {
  const double z = distribution(generator);
  const double y = distribution(generator);
  const double x = distribution(generator);
  return {x, y, z};
}

template <class Distribution, class Generator>
Eigen::Vector2d draw2(Distribution& distribution, Generator& generator) {
  const double y = distribution(generator);
  const double x = distribution(generator);
  return {x, y};
}

}  // namespace volcomp::testutil
