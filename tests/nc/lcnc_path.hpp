#pragma once
// Test side of the LinuxCNC checks: the canonical motions printed by LinuxCNC's interpreter
// (rs274 -g, or lcnc_canon.py at full precision) read into machine coordinates, sampled densely,
// and the check that the machine described by a model, moving along the compensated program,
// puts the tool tip on the original path. Written independently of volcomp::nc's own readers.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::testing {

using Vec3 = Eigen::Vector3d;

struct CanonMotion {
  enum Kind { Rapid, Feed, Arc } kind = Feed;
  Vec3 start = Vec3::Zero();  // machine coordinates, mm
  Vec3 end = Vec3::Zero();
  // Arcs (ARC_FEED): plane axes (first, second, normal), centre in the plane, rotation count.
  int first = 0, second = 1, normal = 2;
  double centerFirst = 0.0, centerSecond = 0.0;
  int rotation = 1;
  bool marked = false;  // preceded by a "(volcomp: ...)" comment: a reversal or lead-in move
  int line = 0;         // line of the canonical text
  long n = -1;          // N word of the program line it came from (-1: none; a motion without one
                        // takes the last N seen: a piece written after its programmed line)
};

/// Reads canonical commands (rs274's text format); throws std::runtime_error on a line it does not
/// understand. Machine position = position * units + G5x + G92 + tool offset. The first motion
/// starts at `start` (mm).
std::vector<CanonMotion> parseCanonical(const std::string& text, const Vec3& start);

/// Points along a motion at most `stepMm` apart (arcs: also within 1e-6 mm of the circle), the
/// start and the end included.
std::vector<Vec3> samplePoints(const CanonMotion& m, double stepMm);

struct PathCheck {
  double tipToOriginalMm = 0.0;  ///< largest distance of a tool-tip sample from the original
  double originalToTipMm = 0.0;  ///< largest distance of an original sample from the tip path
  double rapidEndsMm = 0.0;      ///< largest tool-tip error at the end of a rapid
  long tipSamples = 0;
  long originalSamples = 0;
  long rapids = 0;
  long markedMoves = 0;  ///< reversal and lead-in moves (their interior is not a path)
  std::string worstAt;   ///< where the largest deviation was found (for messages)
  double worst() const;
};

/// The check of the issue: the machine described by `model` follows `compensated` (machine
/// coordinates); its tool tip p(q) - p0(q) + q, with the direction of travel each axis had on the
/// original path there (on the original move with the same N word when the original numbers its
/// moves; else on the nearest original segment), must lie on `original`: both ways (tip samples
/// to the original feed
/// path every `stepMm`, original samples to the tip path every 5 `stepMm`), and every rapid's end.
PathCheck checkCompensation(const model::MachineModel& model,
                            const std::vector<CanonMotion>& original,
                            const std::vector<CanonMotion>& compensated, double stepMm);

}  // namespace volcomp::testing
