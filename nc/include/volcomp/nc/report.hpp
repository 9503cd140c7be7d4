#pragma once
/// What `volcomp nc` measured while compensating a program: counts, offsets, the deviation of the
/// written path from the ideal compensated path (checked, not assumed), points outside the
/// model's travel, time per stage.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace volcomp::nc {

/// A program line listed in the report (first occurrences only, see NcReport::kMaxListed).
struct ListedLine {
  long line = 0;
  std::uint8_t axes = 0;  ///< axes concerned (bit K), where it applies
};

struct NcReport {
  static constexpr std::size_t kMaxListed = 100;

  std::string input;
  std::string format;  ///< "ngc" or "canon"
  double toleranceMm = 0.0;
  double checkStepMm = 0.0;
  int decimalsMm = 0;
  int decimalsInch = 0;

  long linesIn = 0;
  long linesOut = 0;
  long rapidMoves = 0;
  long feedMoves = 0;  ///< G1 (STRAIGHT_FEED)
  long arcMoves = 0;   ///< G2, G3 (ARC_FEED)
  long motionLinesOut = 0;
  long piecesAdded = 0;    ///< motion lines written beyond one per programmed move
  long reversalMoves = 0;  ///< moves inserted where a bidirectional axis changes direction

  // Compensation offsets at the written vertices (mm).
  long vertices = 0;
  double peakOffsetMm = 0.0;
  double sumSqOffsetMm = 0.0;  ///< sum of |o|^2; RMS = sqrt(sum / vertices)

  // Deviation of the written polyline from the ideal compensated path (mm).
  long checkPoints = 0;
  double maxDeviationMm = 0.0;  ///< largest deviation at a check point
  double maxBoundMm = 0.0;      ///< largest (deviation + curvature allowance) of a piece
  long unresolvedPieces = 0;    ///< pieces accepted at the splitting limit above the tolerance

  // Problems, with the first lines where they occur.
  long outsideTravel = 0;  ///< vertices or check points with an axis outside the travel
  std::vector<ListedLine> outsideTravelLines;
  long notConverged = 0;
  std::vector<ListedLine> notConvergedLines;
  long uncompensatedMoves = 0;  ///< position not known yet: copied unchanged
  std::vector<ListedLine> uncompensatedLines;
  long endOnlyMoves = 0;  ///< feed moves from an unknown start: end point only
  std::vector<ListedLine> endOnlyLines;
  std::map<std::string, long> ignoredCanonical;  ///< canonical commands without an effect here

  long offsetSolves = 0;  ///< offsets solved (vertices and check points)

  // Time (s).
  double timeS = 0.0;
  double readS = 0.0;     ///< reading and interpreting lines
  double offsetsS = 0.0;  ///< solving offsets
  double splitS = 0.0;    ///< planning, checking and splitting (without the offset solves)
  double writeS = 0.0;    ///< formatting and writing

  double rmsOffsetMm() const;
  /// Adds `line` to a list (up to kMaxListed entries; the same line once).
  static void list(std::vector<ListedLine>& lines, long line, std::uint8_t axes = 0);
};

}  // namespace volcomp::nc
