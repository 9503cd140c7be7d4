#include "model_builders.hpp"

#include <cmath>

namespace volcomp::model::testing {

TableSpec smoothTable(double lo, double hi, int n, double amplitude, double phase,
                      Interpolation kind) {
  TableSpec table;
  table.interpolation = kind;
  for (int i = 0; i < n; ++i) {
    const double x = lo + (hi - lo) * i / (n - 1);
    table.positionsMm.push_back(x);
    table.values.push_back(amplitude * std::sin(phase + 3.0 * (x - lo) / (hi - lo)));
  }
  return table;
}

MachineModelSpec fullModel(const std::string& topology, int nodes, double maxAngleRad) {
  MachineModelSpec spec;
  spec.name = "full 21-component test model";
  spec.topology = topology;
  const std::array<std::array<double, 2>, 3> travel = {{{0, 850}, {0, 500}, {-500, 0}}};
  for (int k = 0; k < 3; ++k) spec.travelMm[k] = travel[k];
  spec.toolMm = Eigen::Vector3d(0, 0, 120);
  spec.workpieceMm = Eigen::Vector3d(10, -5, 30);
  for (int k = 0; k < 3; ++k) {
    for (int kind = 0; kind < 6; ++kind) {
      const double amplitude = kind < 3 ? 0.02 : maxAngleRad;
      const Interpolation interpolation =
          (kind % 2 == 0) ? Interpolation::Linear : Interpolation::Cubic;
      spec.motion[k * 6 + kind] =
          smoothTable(travel[k][0], travel[k][1], nodes, amplitude, 0.3 * kind + k, interpolation);
    }
  }
  spec.locationRad[locationIndex(Axis::Y, 2)] = 18.5e-6;   // EC0Y
  spec.locationRad[locationIndex(Axis::Z, 1)] = -12.0e-6;  // EB0Z
  spec.locationRad[locationIndex(Axis::Z, 0)] = 7.0e-6;    // EA0Z
  return spec;
}

MachineModelSpec randomModel(std::mt19937& rng, double maxAngleRad, double travelMm,
                             double maxOffsetMm) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, 23);
  const std::vector<std::string> topologies = allTopologies();
  MachineModelSpec spec;
  spec.topology = topologies[pick(rng)];
  for (int k = 0; k < 3; ++k) spec.travelMm[k] = std::array<double, 2>{-travelMm, travelMm};
  spec.toolMm = maxOffsetMm * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  spec.workpieceMm = maxOffsetMm * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  for (int i = 0; i < 18; ++i) {
    const bool angle = i % 6 >= 3;
    // Tables and polynomials are built so that |value| <= amplitude over the travel.
    const double amplitude = angle ? maxAngleRad : 0.02;
    switch (pick(rng) % 5) {
      case 0:
        spec.motion[i] = amplitude * unit(rng);
        break;
      case 1:
        spec.motion[i] =
            smoothTable(-travelMm, travelMm, 21, amplitude, 3.0 * unit(rng), Interpolation::Linear);
        break;
      case 2:
        // 0.9: a natural spline through smooth data overshoots the nodes only slightly.
        spec.motion[i] = smoothTable(-travelMm, travelMm, 41, 0.9 * amplitude, 3.0 * unit(rng),
                                     Interpolation::Cubic);
        break;
      case 3:
        spec.motion[i] = smoothTable(-travelMm, travelMm, 11, 0.9 * amplitude, 3.0 * unit(rng),
                                     Interpolation::Quadratic);
        break;
      default: {
        const double c1 = 0.5 * amplitude * unit(rng) / travelMm;
        const double c2 = 0.5 * amplitude * unit(rng) / (travelMm * travelMm);
        spec.motion[i] = PolynomialSpec{{0.0, c1, c2}};
        break;
      }
    }
  }
  for (double& location : spec.locationRad) location = maxAngleRad * unit(rng);
  GridSpec flat;
  flat.component = 2;
  flat.over = {Axis::X, Axis::Y};
  flat.axesMm = {{-travelMm, 0.0, travelMm}, {-travelMm, travelMm}};
  for (int i = 0; i < 6; ++i) flat.valuesMm.push_back(0.01 * unit(rng));
  GridSpec volume;
  volume.component = 0;
  volume.over = {Axis::Z, Axis::X, Axis::Y};
  volume.axesMm = {{-travelMm, travelMm}, {-travelMm, travelMm}, {-travelMm, 0.0, travelMm}};
  for (int i = 0; i < 12; ++i) volume.valuesMm.push_back(0.01 * unit(rng));
  spec.grids = {flat, volume};
  return spec;
}

}  // namespace volcomp::model::testing
