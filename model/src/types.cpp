#include "volcomp/model/types.hpp"

namespace volcomp::model {

namespace {
constexpr char kAxisLetter[3] = {'X', 'Y', 'Z'};
constexpr char kKindLetter[6] = {'X', 'Y', 'Z', 'A', 'B', 'C'};
constexpr char kRotationLetter[3] = {'A', 'B', 'C'};
}  // namespace

std::optional<Axis> axisFromName(std::string_view name) noexcept {
  if (name.size() != 1) return std::nullopt;
  for (std::uint8_t i = 0; i < 3; ++i) {
    if (name[0] == kAxisLetter[i]) return static_cast<Axis>(i);
  }
  return std::nullopt;
}

std::string motionName(int index) {
  if (index < 0 || index >= 18) {
    throw ModelError("motion error index " + std::to_string(index) + " is outside 0..17");
  }
  return std::string{'E', kKindLetter[index % 6], kAxisLetter[index / 6]};
}

std::string locationName(int index) {
  if (index < 0 || index >= 9) {
    throw ModelError("location error index " + std::to_string(index) + " is outside 0..8");
  }
  return std::string{'E', kRotationLetter[index % 3], '0', kAxisLetter[index / 3]};
}

}  // namespace volcomp::model
