#pragma once
/// Writers of controller tables (docs/export.md states the sources and sign conventions).
///
/// LinuxCNC `COMP_FILE` (per joint, `[JOINT_n]COMP_FILE` / `COMP_FILE_TYPE` in the INI): one
/// "nominal forward reverse" triplet per line, nominal strictly increasing, at most 256 lines, in
/// machine units (mm here), no comments (LinuxCNC stops reading at the first line that is not
/// three numbers). LinuxCNC looks the table up at the commanded joint position, interpolates
/// linearly, holds the end values, takes the forward column while the joint's commanded velocity
/// is > 0 and the reverse column while it is < 0, and adds a "trim" to the commanded position
/// (motor-pos-cmd = pos-cmd + trim, ramped):
///   type 0: forward/reverse are where the joint really is when commanded `nominal`
///           = nominal + e; LinuxCNC's trim is nominal - forward = -e;
///   type 1: forward/reverse are the trims themselves = -e.
/// (Its INI documentation describes type 1 as "how far from nominal" with an example of the
/// opposite sign; the loader in src/emc/motion/usrmotintf.cc, which a test confirms in LinuxCNC
/// itself, is what is written here.)
///
/// Siemens 840D, "Extended Functions: Compensations (K3)": LEC/MSEC `$AA_ENC_COMP[e,N,AXi]` with
/// `_STEP`, `_MIN`, `_MAX`, `_IS_MODULO` in a part program `%_N_AX_EEC_INI`; sag/angularity
/// compensation CEC `$AN_CEC[t,N]` with `_INPUT_AXIS`, `_OUTPUT_AXIS`, `_STEP`, `_MIN`, `_MAX`,
/// `_DIRECTION`, `_MULT_BY_TABLE`, `_IS_MODULO` in `%_N_NC_CEC_INI`. Both interpolate linearly
/// between equidistant points and hold the end values; both modify the axis' actual value, so a
/// positive compensation value moves the axis in the negative direction (K3): the value written
/// is the error itself, e (mm).

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include "volcomp/metrology/axis_tables.hpp"

namespace volcomp::metrology {

/// Largest table LinuxCNC 2.9 accepts per joint (EMCMOT_COMP_SIZE).
inline constexpr std::size_t kLinuxCncMaxPoints = 256;

/// One COMP_FILE from the forward and reverse curves of one axis (the same table twice when it is
/// not direction-dependent). Both tables must share the grid. `type` is 0 or 1.
void writeLinuxCncCompFile(std::ostream& out, const AxisTable& forward, const AxisTable& reverse,
                           int type);

/// Lines written at the top of a Siemens part program as comments (';').
using CommentLines = std::vector<std::string>;

/// `%_N_AX_EEC_INI`: one LEC table per table in `tables` (each input == output, direction 0),
/// for measuring system `encoder` (0 or 1), axis names indexed by Axis (e.g. "AX1", "X1").
void writeSiemensLec(std::ostream& out, const std::vector<AxisTable>& tables,
                     const std::array<std::string, 3>& axisNames, int encoder,
                     const CommentLines& comments);

/// `%_N_NC_CEC_INI`: tables numbered t = 0, 1, ... in the order given.
void writeSiemensCec(std::ostream& out, const std::vector<AxisTable>& tables,
                     const std::array<std::string, 3>& axisNames, const CommentLines& comments);

/// A plain CSV of one component: header `position_mm,value_<unit>[,value_negative_<unit>]`, the
/// component's own value (its sign as in the model file) on the grid, in um (translations) or
/// urad (rotations), full precision.
void writeComponentCsv(std::ostream& out, const model::MachineModelSpec& spec,
                       const std::string& name, const AxisGrid& grid);

}  // namespace volcomp::metrology
