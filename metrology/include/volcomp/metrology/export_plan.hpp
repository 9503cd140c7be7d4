#pragma once
/// Which components of a model a controller's tables can carry, sampled as AxisTables, and which
/// they cannot (with the reason, for the user).
///
/// - LinuxCNC (`COMP_FILE` per joint): a joint's table corrects that joint as a function of its
///   own position, in two curves (moving forward, moving in reverse): the positioning components
///   EXX, EYY, EZZ (values / values_negative where bidirectional).
/// - Siemens 840D: leadscrew error compensation (LEC/MSEC, `$AA_ENC_COMP`) carries the
///   positioning components (the mean of a bidirectional table); sag compensation (CEC,
///   `$AN_CEC`, one input and one output axis per table) carries straightness (EYX: input X,
///   output Y), squareness (EC0Y: input Y, output X; "angularity compensation") and the
///   direction-dependent rest of bidirectional positioning (input = output, $AN_CEC_DIRECTION
///   +1 / -1, values minus their mean), the way Siemens builds direction-dependent LEC.
/// Never carried: angular error motions (their Abbe errors depend on the other axes and the tool
/// length) and grid maps (2-D / 3-D); they need volumetric compensation (volcompd).

#include <string>
#include <vector>

#include "volcomp/metrology/axis_tables.hpp"

namespace volcomp::metrology {

struct ExportPlan {
  std::vector<AxisTable> tables;
  /// One line per carried component: "EXX -> X (forward and reverse curves)".
  std::vector<std::string> carried;
  /// One line per component present in the model that the tables cannot carry, with the reason.
  std::vector<std::string> notCarried;
};

/// Grid steps per axis (mm, 0 = automatic, see makeGrid).
using GridSteps = std::array<double, 3>;

ExportPlan planLinuxCnc(const model::MachineModelSpec& spec, const GridSteps& steps);
ExportPlan planSiemens(const model::MachineModelSpec& spec, const GridSteps& steps);
/// One component by name (a motion error such as "EXX", "EBX" or a location error such as
/// "EC0Y") as a 1-D table. Translations and squareness give an AxisTable (so that the error left
/// when it alone is applied can be computed); an angular motion gives none. Throws
/// std::invalid_argument for an unknown name.
ExportPlan planComponent(const model::MachineModelSpec& spec, const std::string& name,
                         const GridSteps& steps);

/// The grid the plans use along `axis`.
AxisGrid planGrid(const model::MachineModelSpec& spec, model::Axis axis, const GridSteps& steps);

}  // namespace volcomp::metrology
