#pragma once
/// Machine topology strings (docs/model-file.md "Topology"), e.g. "XYFZ": letters before F are
/// workpiece-side axes listed from the workpiece to the frame; letters after F are tool-side axes
/// from the frame to the tool.

#include <string>
#include <string_view>
#include <vector>

#include "volcomp/model/types.hpp"

namespace volcomp::model {

class Topology {
 public:
  /// Throws ModelError unless `text` holds F once and each of X, Y, Z once (upper case).
  static Topology parse(std::string_view text);

  const std::string& text() const noexcept { return text_; }
  /// Workpiece-side axes ordered from the FRAME outward to the workpiece (composition order of
  /// H_FW = C_{Wn} ... C_{W1}); for "XYFZ" this is {Y, X}.
  const std::vector<Axis>& workpieceSideFromFrame() const noexcept { return workpiece_; }
  /// Tool-side axes ordered from the frame outward to the tool; for "XYFZ" this is {Z}.
  const std::vector<Axis>& toolSideFromFrame() const noexcept { return tool_; }
  /// True when `axis` carries the workpiece side (moves opposite to the commanded direction).
  bool isWorkpieceSide(Axis axis) const noexcept;

 private:
  std::string text_;
  std::vector<Axis> workpiece_;
  std::vector<Axis> tool_;
};

/// All 3-axis topology strings (the 24 permutations of X, Y, Z, F); for exhaustive tests.
std::vector<std::string> allTopologies();

}  // namespace volcomp::model
