#pragma once
/// The state an NC interpreter keeps between lines, shared by the RS274/NGC reader and the reader
/// of LinuxCNC canonical commands: units, distance mode, the frame from program coordinates to
/// machine axis positions, the current position and which of its axes are known.

#include <cstdint>

#include "volcomp/nc/move.hpp"
#include "volcomp/nc/setup.hpp"

namespace volcomp::nc {

/// Program coordinates p (program units) <-> machine axis positions q (mm):
///   q = p * unitMm + shiftMm,  shiftMm = G5x offset + G92 offset + tool offset.
struct Frame {
  Vec3 shiftMm = Vec3::Zero();
  double unitMm = 1.0;
  Vec3 toMachine(const Vec3& p) const noexcept { return p * unitMm + shiftMm; }
  Vec3 toProgram(const Vec3& q) const noexcept { return (q - shiftMm) / unitMm; }
};

/// How the output writes the coordinates of a motion line.
struct PrintMode {
  Frame frame;
  bool incremental = false;         ///< G91: differences of printed positions
  bool machineCoordinates = false;  ///< G53: frame shift 0, "G53" written on the line
  int decimals = 5;
};

/// Current position: machine coordinates (mm) and which axes are known (bit K). Axes become
/// known when a program move (or --start) sets them.
struct Position {
  Vec3 machineMm = Vec3::Zero();
  std::uint8_t known = 0;
  bool allKnown() const noexcept { return known == 7; }
};

}  // namespace volcomp::nc
