#pragma once
/// An NC program as the simulated machine's path: its moves in machine coordinates, read with
/// volcomp's NC interpreter (RS274/NGC in the subset of `volcomp nc`, or LinuxCNC canonical
/// commands), with work offsets and a tool table as `volcomp nc` takes them.

#include <optional>
#include <string>
#include <vector>

#include "volcomp/nc/move.hpp"
#include "volcomp/sim/path.hpp"

namespace volcomp::sim {

struct NcProgramSpec {
  std::string file;
  std::vector<std::string> workOffsets;  ///< .var / .json files
  std::string toolTable;                 ///< .tbl file or ""
  std::string machineUnits = "mm";       ///< units of .var and .tbl values: "mm" or "inch"
  std::optional<Vec3> startMm;           ///< machine position at the start, when known
};

struct NcProgramMove {
  nc::Move move;
  long line = 0;
  /// A move `volcomp nc` added at a vertex ("(volcomp: reversal)", "(volcomp: to the compensated
  /// start)"): the machine takes up a reversal there; it is not part of the path.
  bool marked = false;
};

/// The moves whose start and end are known (moves before every axis has been programmed are
/// left out). Throws nc::NcError or config::ConfigError for a bad program or file, and nc::NcError
/// at its line for a move reaching beyond nc::kMaxPositionMm (an end point, or an arc's radius).
std::vector<NcProgramMove> readNcProgram(const NcProgramSpec& spec);

/// Most pieces (straight chords, samples) the simulator splits one move into.
inline constexpr double kMaxPiecesPerMove = 1e7;

/// ceil(wanted), at least 1: the number of pieces of move `m` of program `file`. Throws
/// nc::NcError at the move's line, naming `what` ("chords within 1e-05 mm"), when that is more
/// than kMaxPiecesPerMove (or not a number).
int piecesOf(const NcProgramMove& m, double wanted, const std::string& file, const char* what);

/// Pieces that keep arc `m` within `toleranceMm` of its chords (1 for a straight move), through
/// piecesOf.
int arcChords(const NcProgramMove& m, double toleranceMm, const std::string& file);

/// The program's feed and rapid moves as a closed polyline path (arcs within 1e-4 mm), travelled
/// at `feedMmMin`.
Path ncProgramPath(const NcProgramSpec& spec, double feedMmMin);

}  // namespace volcomp::sim
