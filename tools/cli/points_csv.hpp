#pragma once
// The points CSV of `volcomp eval --points`: a header `x,y,z` (any case, a UTF-8 byte-order mark
// before it tolerated), then one point per row, three finite numbers in mm. Blank lines are
// skipped; spaces, tabs and CRLF line ends are tolerated; a line is at most 1 MiB.

#include <cstddef>
#include <istream>
#include <string>

#include <Eigen/Core>

#include "volcomp/config/text_input.hpp"

namespace volcomp::cli {

class PointsCsvReader {
 public:
  /// Reads up to and including the header. Throws config::ConfigError(file, "line N", what was
  /// expected) when the first line that is not blank is not the header, or the input is empty.
  PointsCsvReader(std::istream& in, const std::string& file);

  /// The next point (mm); false at the end of the input. Throws config::ConfigError naming the
  /// line and showing (quoted, shortened) what it holds when a row is not three finite numbers.
  bool next(Eigen::Vector3d& qMm);
  /// Line of the point last returned (1-based, the header counted).
  std::size_t lineNumber() const noexcept { return lines_.lineNumber(); }

 private:
  config::LineReader lines_;
  std::string file_;
};

}  // namespace volcomp::cli
