#pragma once
// `volcomp eval MODEL --points IN.csv --out OUT.csv`: batch evaluation of a CSV file of points.

#include <cstddef>
#include <string>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::cli {

struct PointsSummary {
  std::size_t rows = 0;
  std::size_t clampedRows = 0;       ///< rows with an axis outside its travel
  std::size_t firstClampedLine = 0;  ///< line number in the input file (1 = header)
  std::size_t notConvergedRows = 0;  ///< rows whose offset solve did not converge
  std::size_t firstNotConvergedLine = 0;
};

/// Reads IN (header `x,y,z`, whitespace and CRLF tolerated, blank lines skipped), writes OUT with
/// header `x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz` and one row per input row (mm, rad; shortest
/// round-trip doubles). Throws config::ConfigError naming the file and line on a bad row or an
/// I/O failure; a partly written OUT is then removed. Progress goes to stderr every 100000 rows
/// when stderr is a terminal.
PointsSummary evaluatePointsFile(const model::MachineModel& model,
                                 const model::Directions& directions, model::EvalMode mode,
                                 const std::string& inPath, const std::string& outPath);

}  // namespace volcomp::cli
