#pragma once
// `volcomp eval MODEL --points IN.csv --out OUT.csv`: batch evaluation of a CSV file of points.

#include <cstddef>
#include <string>
#include <vector>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::cli {

struct PointsSummary {
  std::size_t rows = 0;
  std::size_t clampedRows = 0;       ///< rows with an axis outside its travel
  std::size_t firstClampedLine = 0;  ///< line number in the input file (1 = header)
  std::size_t notConvergedRows = 0;  ///< rows whose offset solve did not converge
  std::size_t firstNotConvergedLine = 0;
  /// The distinct tool offsets evaluated (mm) and the first line of each.
  std::vector<Eigen::Vector3d> toolsMm;
  std::vector<std::size_t> toolLines;
};

/// Reads IN with config::CsvReader (the schema of points_csv.hpp): columns x,y,z, optionally
/// tx,ty,tz (the tool of each point, else the model's) and direction (e.g. +-+, else
/// `directions`), in any order, with comments and unit suffixes; columns of measurement files and
/// of eval's output are accepted and ignored. Writes OUT with header
/// `x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz` (then tx,ty,tz and direction when IN has them) and one row
/// per input row (mm, rad; shortest round-trip doubles) through output::OutputFile: OUT is
/// replaced only when every row was good, and never when it is IN or one of `otherInputs` (the
/// model file). Throws config::ConfigError naming the file, line and column on a bad row,
/// output::OutputError when OUT cannot be written. Progress goes to stderr every 100000 rows when
/// stderr is a terminal.
PointsSummary evaluatePointsFile(const model::MachineModel& model,
                                 const model::Directions& directions, model::EvalMode mode,
                                 const std::string& inPath, const std::string& outPath,
                                 const std::vector<std::string>& otherInputs = {});

}  // namespace volcomp::cli
