#pragma once
// Model specs shared by the model tests and the allocation test.

#include <random>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::model::testing {

/// Table over [lo, hi] with n uniform nodes and values amplitude * sin(phase + 3 x / (hi - lo)).
TableSpec smoothTable(double lo, double hi, int n, double amplitude, double phase,
                      Interpolation kind);

/// A full 21-component model (18 motion errors, 3 squareness) with realistic sizes: translations
/// up to ~20 um, angles up to ~`maxAngleRad`, tables of `nodes` uniform points over the travel,
/// linear and cubic mixed, a quadratic and a polynomial, optionally bidirectional X tables.
MachineModelSpec fullModel(const std::string& topology, int nodes = 101, double maxAngleRad = 1e-3);

/// Random model for property tests: random topology, components of every kind, angles up to
/// `maxAngleRad`, tool and workpiece offsets up to `maxOffsetMm` per component, travel
/// [-travelMm, travelMm], and a 2-D and a 3-D grid.
MachineModelSpec randomModel(std::mt19937& rng, double maxAngleRad, double travelMm,
                             double maxOffsetMm);

}  // namespace volcomp::model::testing
