#pragma once
/// One-dimensional compensation tables sampled from a model, the kind a controller loads: as the
/// input axis moves, the controller displaces the output axis so as to cancel a tabulated error.
///
/// A table holds e(q), the part of the volumetric error E = p - p0 (actual minus nominal, tool
/// relative to workpiece, mm, model file definition) along the output axis that its components
/// cause, on a uniform grid of the commanded input-axis position q. It is computed with the model
/// library itself: a model holding only those components is evaluated along the input axis, so
/// the tool-side / workpiece-side signs come from the composition, not from a second derivation
/// (on a tool-side axis EXX adds +EXX to E_x, on a workpiece-side axis -EXX). Translations and
/// squareness give e(q) exactly, independent of the other axes; angular error motions do not fit a
/// 1-D table (their Abbe errors depend on the other axes and the tool) and are never tabulated.
/// Between grid points and beyond the ends, a table is read as every controller here reads it:
/// linear interpolation, end values held.

#include <cstdint>
#include <string>
#include <vector>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::metrology {

/// A uniform grid along one axis (mm): startMm + i * stepMm, i = 0..count-1.
struct AxisGrid {
  double startMm = 0.0;
  double stepMm = 1.0;
  std::size_t count = 0;
  double positionMm(std::size_t i) const noexcept {
    return startMm + static_cast<double>(i) * stepMm;
  }
  double endMm() const noexcept { return positionMm(count - 1); }
};

struct AxisTable {
  model::Axis input = model::Axis::X;
  model::Axis output = model::Axis::X;
  /// 0: applies in both directions; +1 only while the input axis moves in +; -1 only in -.
  int direction = 0;
  AxisGrid grid;
  /// e(q_i), mm: the error to cancel (the controller moves the output axis by -e).
  std::vector<double> errorMm;
  /// ISO 230-1 names of the components it carries ("EXX", "EYX", "EC0Y").
  std::vector<std::string> components;

  /// e at q (linear interpolation, end values held).
  double errorAt(double qMm) const noexcept;
};

/// Positions covered along `axis`: its travel when the model gives one, else the range of its
/// tables, else [0, 0]. `fromTravel` tells which.
struct AxisRange {
  double lowMm = 0.0, highMm = 0.0;
  bool fromTravel = false;
};
AxisRange axisRange(const model::MachineModelSpec& spec, model::Axis axis);

/// A uniform grid from range.lowMm covering range.highMm: `stepMm` when > 0, else the largest of
/// 1, 2, 2.5, 5 x 10^k mm that gives at most 101 points. The last point may lie beyond highMm (the
/// grid holds a whole number of steps).
AxisGrid makeGrid(const AxisRange& range, double stepMm);

/// e(q) of the given components (motion indices 0..17 by model::motionIndex, location indices
/// 0..8 by model::locationIndex) along `input`, projected on `output`, with the input axis moving
/// in `direction` (Unknown: the mean of bidirectional tables).
AxisTable sampleTable(const model::MachineModelSpec& spec, const std::vector<int>& motion,
                      const std::vector<int>& location, model::Axis input, model::Axis output,
                      const AxisGrid& grid, model::Direction direction);

/// Whether a motion component is given (not the zero constant) / bidirectional in `spec`.
bool isPresent(const model::ErrorFunctionSpec& function);
bool isBidirectional(const model::ErrorFunctionSpec& function);

/// "X", "Y", "Z".
const char* axisName(model::Axis axis) noexcept;

}  // namespace volcomp::metrology
