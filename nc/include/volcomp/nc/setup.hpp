#pragma once
/// What a controller knows besides the program: work coordinate systems (G54 ... G59.3), the
/// G92 offset in effect, and the tool table (G43). All lengths inside are mm.
///
/// Machine axis position of a programmed point p (tool tip, active work coordinates):
///   q = p + G5x offset + G92 offset + tool offset (while G43 is active)          (mm)
/// as LinuxCNC computes it. Coordinate system rotation (G10 L2 R) is not supported.
///
/// Readers (each throws NcError or config::ConfigError naming the file, line or key path):
/// - LinuxCNC parameter files (.var): "NUMBER VALUE" per line; 5220 (active system, 1..9),
///   5221 + 20 k .. 5223 + 20 k (X, Y, Z of system k = 0..8), 5230 + 20 k (its rotation, must
///   be 0), 5211 .. 5213 (G92 offset, used when 5210 is 1). Values are in machine units
///   ([TRAJ]LINEAR_UNITS), given by the caller.
/// - LinuxCNC tool tables (.tbl): "T<n> P<pocket> X.. Y.. Z.. D.. ;comment"; X, Y, Z are the
///   tool offsets G43 applies, in machine units.
/// - A small JSON file (format "volcomp-work-offsets/1", see docs/nc.md):
///   {"units": "mm"|"inch", "active": "G54", "coordinate_systems": {"G54": [x, y, z], ...},
///    "g92": [x, y, z], "tools": {"1": [x, y, z] or z}}

#include <array>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

namespace volcomp::nc {

enum class LengthUnit { Mm, Inch };

/// mm per unit: 1 or 25.4.
double mmPerUnit(LengthUnit unit) noexcept;

inline constexpr int kCoordinateSystems = 9;

/// "G54" ... "G59", "G59.1", "G59.2", "G59.3" for index 0 .. 8.
const char* coordinateSystemName(int index) noexcept;
/// Index 0 .. 8 of a name as above (case-insensitive), or -1.
int coordinateSystemIndex(std::string_view name) noexcept;

struct WorkOffsets {
  std::array<Eigen::Vector3d, kCoordinateSystems> systemsMm{};
  /// The coordinate system active when the program starts (index 0 .. 8; LinuxCNC keeps it in
  /// parameter 5220).
  int active = 0;
  /// Rotation about Z of each system (deg, G10 L2 R); the interpreter rejects selecting a system
  /// whose rotation is not 0.
  std::array<double, kCoordinateSystems> rotationDeg{};
  /// G92 offset in effect (LinuxCNC keeps it in 5211 .. 5213 across runs).
  Eigen::Vector3d g92Mm = Eigen::Vector3d::Zero();
  WorkOffsets() {
    for (auto& s : systemsMm) s.setZero();
  }
};

/// Tool number -> tool offsets (X, Y, Z) in mm, as G43 H<n> applies them.
using ToolTable = std::map<int, Eigen::Vector3d>;

/// Parses the text of a LinuxCNC .var file into `offsets` (parameters not listed are ignored).
/// `file` names the source in messages.
void parseVarText(std::string_view text, const std::string& file, LengthUnit machineUnits,
                  WorkOffsets& offsets);
/// Parses the text of a LinuxCNC tool table into `tools` (entries are added or replaced).
void parseToolTableText(std::string_view text, const std::string& file, LengthUnit machineUnits,
                        ToolTable& tools);
/// Parses a JSON work-offset document (text) into `offsets` and `tools`.
void parseWorkOffsetsJson(std::string_view text, const std::string& file, WorkOffsets& offsets,
                          ToolTable& tools);

/// Reads a file by its kind: ".var" -> parseVarText, ".json" -> parseWorkOffsetsJson (anything
/// else is rejected). Throws NcError / config::ConfigError.
void readWorkOffsetsFile(const std::string& path, LengthUnit machineUnits, WorkOffsets& offsets,
                         ToolTable& tools);
/// Reads a .tbl file.
void readToolTableFile(const std::string& path, LengthUnit machineUnits, ToolTable& tools);

/// The whole content of a text file; throws NcError(path, 0, 0, reason) when it cannot be read.
std::string readTextFile(const std::string& path);

}  // namespace volcomp::nc
