#pragma once
/// Basic vocabulary of the volumetric error model (docs/model.md).
/// Units inside the model are always mm for lengths and rad for angles; the config layer converts.

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace volcomp::model {

/// A linear machine axis. The integer value is the index into q = (x, y, z).
enum class Axis : std::uint8_t { X = 0, Y = 1, Z = 2 };

/// The axis named "X", "Y" or "Z" (upper case, nothing around it); nullopt for any other text.
std::optional<Axis> axisFromName(std::string_view name) noexcept;

/// Direction in which an axis last moved; selects the curve of a bidirectional table
/// (`values` for Positive, `values_negative` for Negative, their mean for Unknown).
enum class Direction : std::int8_t { Negative = -1, Unknown = 0, Positive = 1 };

/// One direction per axis, indexed by Axis.
using Directions = std::array<Direction, 3>;

/// Kind of an error motion of one axis, in the order of ISO 230-1 names EXK, EYK, EZK, EAK, EBK,
/// ECK: three translations (mm) along X, Y, Z and three rotations (rad) about X, Y, Z.
enum class MotionKind : std::uint8_t { EX = 0, EY = 1, EZ = 2, EA = 3, EB = 4, EC = 5 };

/// Index of motion error `kind` of axis `axis` in an 18-element array: axis * 6 + kind.
/// E.g. EBX (pitch of X) = motionIndex(Axis::X, MotionKind::EB) = 4.
constexpr int motionIndex(Axis axis, MotionKind kind) noexcept {
  return static_cast<int>(axis) * 6 + static_cast<int>(kind);
}

/// Index of location error EA0K / EB0K / EC0K (rotation about X, Y, Z of the line of motion of
/// axis K) in a 9-element array: axis * 3 + (0 for A, 1 for B, 2 for C). E.g. EC0Y = 5.
constexpr int locationIndex(Axis axis, int rotationAbout) noexcept {
  return static_cast<int>(axis) * 3 + rotationAbout;
}

/// ISO 230-1 name of motion index i (0..17), e.g. "EXX", "EBX", "ECZ".
std::string motionName(int index);
/// ISO 230-1 name of location index i (0..8), e.g. "EA0X", "EC0Y".
std::string locationName(int index);

/// Thrown when a model is constructed from inconsistent data. The config layer validates files
/// first and reports key paths; this is the backstop for programmatic construction.
class ModelError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace volcomp::model
