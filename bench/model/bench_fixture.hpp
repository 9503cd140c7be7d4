#pragma once
// The benchmark model and sweep shared by bench_model (Google Benchmark, time) and
// model_instruction_count (fixed work for callgrind): a full 21-component XYFZ model (18 motion
// errors as 101-point uniform tables, linear and cubic mixed, plus EC0Y, EB0Z, EA0Z squareness)
// and a sweep of points through the working volume.

#include <array>
#include <cmath>
#include <vector>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::model::bench {

constexpr int kNodes = 101;
constexpr int kPoints = 4096;

inline TableSpec smoothTable(double lo, double hi, double amplitude, double phase,
                             Interpolation kind) {
  TableSpec table;
  table.interpolation = kind;
  for (int i = 0; i < kNodes; ++i) {
    const double x = lo + (hi - lo) * i / (kNodes - 1);
    table.positionsMm.push_back(x);
    table.values.push_back(amplitude * std::sin(phase + 3.0 * (x - lo) / (hi - lo)));
  }
  return table;
}

inline MachineModel fullModel() {
  MachineModelSpec spec;
  spec.topology = "XYFZ";
  const std::array<std::array<double, 2>, 3> travel = {{{0, 850}, {0, 500}, {-500, 0}}};
  for (int k = 0; k < 3; ++k) spec.travelMm[k] = travel[k];
  spec.toolMm = Eigen::Vector3d(0, 0, 120);
  for (int k = 0; k < 3; ++k) {
    for (int kind = 0; kind < 6; ++kind) {
      const double amplitude = kind < 3 ? 0.02 : 5e-5;
      const Interpolation interpolation =
          (kind % 2 == 0) ? Interpolation::Linear : Interpolation::Cubic;
      spec.motion[k * 6 + kind] =
          smoothTable(travel[k][0], travel[k][1], amplitude, 0.3 * kind + k, interpolation);
    }
  }
  spec.locationRad[locationIndex(Axis::Y, 2)] = 18.5e-6;
  spec.locationRad[locationIndex(Axis::Z, 1)] = -12.0e-6;
  spec.locationRad[locationIndex(Axis::Z, 0)] = 7.0e-6;
  return MachineModel(spec);
}

// A sweep along a diagonal-ish path through the volume (consecutive points close together, as in
// a live loop), covering every table interval.
inline std::vector<Eigen::Vector3d> sweep() {
  std::vector<Eigen::Vector3d> points;
  points.reserve(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    const double s = static_cast<double>(i) / (kPoints - 1);
    points.emplace_back(850 * s, 250 + 240 * std::sin(6.283 * s), -500 * (1 - s) * s * 4);
  }
  return points;
}

}  // namespace volcomp::model::bench
