#include "volcomp/model/topology.hpp"

#include <algorithm>

namespace volcomp::model {

namespace {

Axis axisOfLetter(char letter) {
  switch (letter) {
    case 'X':
      return Axis::X;
    case 'Y':
      return Axis::Y;
    default:
      return Axis::Z;
  }
}

}  // namespace

Topology Topology::parse(std::string_view text) {
  const std::string quoted = "topology \"" + std::string(text) + "\"";
  if (text.size() != 4) {
    throw ModelError(quoted + ": expected 4 letters holding F once and each of X, Y, Z once");
  }
  int seen[4] = {0, 0, 0, 0};  // X, Y, Z, F
  for (const char c : text) {
    switch (c) {
      case 'X':
        ++seen[0];
        break;
      case 'Y':
        ++seen[1];
        break;
      case 'Z':
        ++seen[2];
        break;
      case 'F':
        ++seen[3];
        break;
      default:
        throw ModelError(quoted + ": unexpected character '" + std::string(1, c) +
                         "', expected only F, X, Y, Z (upper case)");
    }
  }
  if (seen[0] != 1 || seen[1] != 1 || seen[2] != 1 || seen[3] != 1) {
    throw ModelError(quoted + ": expected F once and each of X, Y, Z once");
  }

  Topology topology;
  topology.text_ = std::string(text);
  const std::size_t frame = text.find('F');
  // Letters before F run from the workpiece to the frame; the composition needs frame outward.
  for (std::size_t i = frame; i-- > 0;) {
    topology.workpiece_.push_back(axisOfLetter(text[i]));
  }
  for (std::size_t i = frame + 1; i < text.size(); ++i) {
    topology.tool_.push_back(axisOfLetter(text[i]));
  }
  return topology;
}

bool Topology::isWorkpieceSide(Axis axis) const noexcept {
  return std::find(workpiece_.begin(), workpiece_.end(), axis) != workpiece_.end();
}

std::vector<std::string> allTopologies() {
  std::string letters = "FXYZ";  // sorted, so next_permutation visits all 24
  std::vector<std::string> result;
  do {
    result.push_back(letters);
  } while (std::next_permutation(letters.begin(), letters.end()));
  return result;
}

}  // namespace volcomp::model
