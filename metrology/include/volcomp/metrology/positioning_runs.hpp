#pragma once
/// The raw data of an ISO 230-2 linear positioning test: for each target position P_i, run j and
/// approach direction, the positional deviation x_ij = P_ij - P_i (actual minus target, ISO 230-2
/// 3.1.x; the sign a laser interferometer reports when its reading is set to count with the
/// commanded axis coordinate). Lengths in mm.
///
/// The CSV (docs/iso230-2.md) has one row per reading and a header naming the columns in any
/// order, each length column with its unit:
///   target_<unit>      target position P_i                                  required
///   deviation_<unit>   x_ij = actual - target          (or actual_<unit>: P_ij) one of the two
///   run                run number (integer)                                 required
///   direction          + / up / forward / ↑   or   - / down / reverse / ↓   required
///   axis               X, Y or Z                                            optional
/// Units: nm, um (µm, micron), mm, m, in; written name_unit, "name [unit]" or "name (unit)".
/// Comma- or semicolon-separated (with ';' a decimal comma is accepted); '#' lines and blank lines
/// are skipped; other columns are ignored and listed in `ignoredColumns`.

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "volcomp/model/types.hpp"

namespace volcomp::metrology {

/// One reading of the test.
struct PositioningSample {
  double targetMm = 0.0;
  int run = 0;
  /// Positive: the target was approached moving in the positive direction (↑); Negative (↓).
  model::Direction direction = model::Direction::Positive;
  /// x_ij = P_ij - P_i, mm.
  double deviationMm = 0.0;
  /// Line in the source file (1-based), for messages; 0 when built in code.
  int line = 0;
};

struct PositioningRuns {
  /// Source file name (messages only).
  std::string file;
  /// The axis when known (from the axis column or the axis filter).
  std::optional<model::Axis> axis;
  std::vector<PositioningSample> samples;
  /// Header columns that were not understood and not used.
  std::vector<std::string> ignoredColumns;
};

/// Reads the CSV described above from `input`. With an `axisFilter` only rows of that axis are
/// kept (a file without an axis column is then taken to be of that axis). Throws
/// config::ConfigError naming `file`, the line and column, and what was expected.
PositioningRuns parsePositioningCsv(std::istream& input, const std::string& file,
                                    std::optional<model::Axis> axisFilter = std::nullopt);
/// Same from a file.
PositioningRuns readPositioningCsv(const std::string& path,
                                   std::optional<model::Axis> axisFilter = std::nullopt);

}  // namespace volcomp::metrology
