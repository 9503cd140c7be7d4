#pragma once
/// What the parts of the compensation count into the report as they go: solved
/// points, written vertices, and the time of each stage.

#include <algorithm>
#include <chrono>

#include "volcomp/nc/offset_field.hpp"
#include "volcomp/nc/report.hpp"

namespace volcomp::nc::detail {

using Clock = std::chrono::steady_clock;

/// Seconds from `a` to `b`.
inline double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

/// Counts a solved point outside the travel or not converged, with its program
/// line.
inline void noteSolved(NcReport& report, const OffsetSample& s, long line) {
  if (s.clampedAxes != 0) {
    ++report.outsideTravel;
    NcReport::list(report.outsideTravelLines, line, s.clampedAxes);
  }
  if (!s.converged) {
    ++report.notConverged;
    NcReport::list(report.notConvergedLines, line);
  }
}

/// Counts a written vertex and its offset.
inline void noteVertex(NcReport& report, const OffsetSample& s) {
  ++report.vertices;
  const double o = s.offsetMm.norm();
  report.peakOffsetMm = std::max(report.peakOffsetMm, o);
  report.sumSqOffsetMm += o * o;
}

}  // namespace volcomp::nc::detail
