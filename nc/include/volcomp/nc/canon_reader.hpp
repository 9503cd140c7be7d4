#pragma once
/// Reads the canonical commands printed by LinuxCNC's standalone interpreter (`rs274 -g`, one
/// command per line: "  12 N..... STRAIGHT_FEED(1.0000, 2.0000, 3.0000, 0.0000, 0.0000,
/// 0.0000)") and writes a flat RS274/NGC program that makes the same motions: so any program
/// LinuxCNC can run (parameters, subroutines, loops, canned cycles...) can be compensated after a
/// real interpreter has flattened it.
///
/// Positions of canonical commands are program coordinates in the current length units; the
/// machine position is  q = position + G5x offset + G92 offset + tool offset  (SET_G5X_OFFSET,
/// SET_G92_OFFSET, USE_TOOL_LENGTH_OFFSET). The flat program selects the same coordinate system
/// (G54 ...), sets changed coordinate systems with G10 L2 as the program did, reproduces the tool
/// offset with G43.1 / G49, and writes coordinates relative to the G92 offset in effect when the
/// program started (it has no G92 of its own). Kept: feed (F, G94/G95), spindle (S, M3/M4/M5),
/// tools (T, M6, M61), coolant (M7/M8/M9), dwell (G4), path control (G61/G61.1/G64), stops (M0,
/// M1, M2, M60), comments and messages. Commands without an effect on the motion are counted in
/// the report. Rejected: probing (STRAIGHT_PROBE), rigid tapping, NURBS, spindle-synchronized
/// motion, inverse-time feed, rotary axes, coordinate system rotation.

#include <array>
#include <map>
#include <optional>
#include <string>

#include "volcomp/nc/ngc_interpreter.hpp"
#include "volcomp/nc/program_lines.hpp"
#include "volcomp/nc/report.hpp"

namespace volcomp::nc {

class CanonReader final : public ProgramReader {
 public:
  CanonReader(std::string file, std::optional<Vec3> startMm, Decimals decimals);
  const char* formatName() const noexcept override { return "canon"; }
  const std::string& file() const noexcept override { return file_; }
  void header(std::string& out) override;
  void read(std::string_view line, std::string_view eol, long number, Chunk& chunk) override;
  void trailer(std::string& out) override;

  /// Canonical commands that have no effect on the flat program, with how often they occurred.
  const std::map<std::string, long>& ignored() const noexcept { return ignored_; }

  /// True when `line` looks like a line of rs274 -g output.
  static bool looksCanonical(std::string_view line);

 private:
  struct Arguments;
  /// One canonical call being read, and the handlers of the calls (a table by name).
  struct Call;
  struct Commands;
  /// Splits the arguments between the parentheses at blanks and commas.
  void splitArguments(Arguments& args, long number) const;
  [[noreturn]] void fail(long number, std::size_t offset, const std::string& message) const;
  /// Argument `index` of a canonical call as a number; a missing or non-numeric one is an error
  /// at its column.
  double argument(const Arguments& args, std::string_view name, long number, int index) const;
  void motion(const Arguments& args, std::string_view name, long number, std::string_view line,
              std::string_view eol, Chunk& chunk);
  PrintMode printMode() const noexcept;
  void appendLength(std::string& out, double valueMm) const;

  std::string file_;
  Decimals decimals_;
  Position position_;
  LengthUnit units_ = LengthUnit::Mm;
  bool unitsWritten_ = false;
  int plane_ = 0;
  int system_ = -1;
  std::array<std::optional<Vec3>, 9> systemsMm_{};  // as the controller holds them
  Vec3 g5xMm_ = Vec3::Zero();
  Vec3 g92Mm_ = Vec3::Zero();
  std::optional<Vec3> g92StartMm_;
  Vec3 toolMm_ = Vec3::Zero();
  double rotationDeg_ = 0.0;
  bool inverseTime_ = false;
  bool synchronized_ = false;
  bool mist_ = false;
  bool flood_ = false;
  bool programEnd_ = false;
  std::map<std::string, long> ignored_;
};

}  // namespace volcomp::nc
