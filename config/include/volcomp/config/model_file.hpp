#pragma once
/// Model files (the volcomp-model/1 format, docs/model-file.md) <-> model specs, with unit
/// conversion and key-path validation. Everything returned is in internal units (mm, rad).

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "volcomp/config/calibration_record.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::config {

struct ParseOptions {
  /// Calibration templates: a component (or a D-H deviation) may be an object holding an
  /// "identify" key; those raw blocks are returned in ModelDocument::identify and the component
  /// gets its optional "start" value (or 0) in the spec.
  bool allowIdentify = false;
};

/// The length units a file may state for error values: "mm", "um", "nm".
enum class LengthUnit { Millimetre, Micrometre, Nanometre };
/// The angle units a file may state for error values: "rad", "mrad", "urad", "arcsec", "deg".
enum class AngleUnit { Radian, Milliradian, Microradian, Arcsecond, Degree };

/// The unit's name as files and messages write it: "mm", "um", "nm"; "rad", "mrad", "urad",
/// "arcsec", "deg".
const char* unitName(LengthUnit unit) noexcept;
const char* unitName(AngleUnit unit) noexcept;
/// The factor that takes a value in `unit` to mm (1e-3 for um) or rad (pi / 180 for deg).
double toMm(LengthUnit unit) noexcept;
double toRad(AngleUnit unit) noexcept;
/// The unit of a name ("um" -> Micrometre); nullopt for a name that is not one of the units.
std::optional<LengthUnit> lengthUnitFromName(std::string_view name) noexcept;
std::optional<AngleUnit> angleUnitFromName(std::string_view name) noexcept;

/// Units a file states for error values ("error_units"); the factors multiply file values to get
/// mm and rad.
struct ErrorUnits {
  LengthUnit length = LengthUnit::Millimetre;
  AngleUnit angle = AngleUnit::Radian;
  double lengthToMm() const noexcept { return toMm(length); }
  double angleToRad() const noexcept { return toRad(angle); }
  bool operator==(const ErrorUnits&) const = default;
};

/// The largest error values a file may hold before `volcomp check` and volcompd call it
/// implausible for a machine tool (config/model_plausibility.hpp). The defaults; a file may
/// override them with "plausibility": {"max_length_mm": L, "max_angle_rad": A}.
struct PlausibilityLimits {
  double maxLengthMm = 1.0;   ///< |translational error value| and |E(q)|, mm
  double maxAngleRad = 1e-2;  ///< |angular error value|, rad
  bool stated = false;        ///< the file overrides the defaults
};

struct ModelDocument {
  std::string file;
  ErrorUnits units;
  /// The file states "error_units" (a file without it is read as mm and rad, and refused by
  /// the plausibility check: values typed in µm would be read 1000 times too large).
  bool unitsStated = false;
  PlausibilityLimits plausibility;
  /// A 3-axis machine model or a D-H chain.
  std::variant<model::MachineModelSpec, model::DhChainSpec> spec;
  /// With ParseOptions::allowIdentify: key path (e.g. "components.EXX",
  /// "chain.links[1].dalpha") -> the raw "identify" block.
  std::map<std::string, nlohmann::json> identify;
  /// The optional "calibration" block (provenance and measured tools), see calibration_record.hpp.
  std::optional<CalibrationRecord> calibration;
};

/// Reads and validates a model file. Throws ConfigError (file, key path, what was expected).
ModelDocument loadModelFile(const std::string& path, const ParseOptions& options = {});

/// Reads a model file that must be a 3-axis machine model (the daemon and the simulated machine
/// evaluate those only): a D-H chain file is a ConfigError at "chain" saying that `user` (e.g.
/// "live compensation") needs a 3-axis model. Otherwise as loadModelFile.
model::MachineModelSpec loadMachineModelFile(const std::string& path, const std::string& user);

/// Same as loadModelFile for an already parsed document; `file` is used in messages only.
ModelDocument parseModel(const nlohmann::json& document, const std::string& file,
                         const ParseOptions& options = {});

/// Writes a 3-axis model spec as a volcomp-model/1 document in the given error units
/// (round trip: parseModel(writeModel(s, u)) reproduces s).
nlohmann::json writeModel(const model::MachineModelSpec& spec, const ErrorUnits& units = {});
/// Writes a D-H chain spec (angles in degrees as the format says).
nlohmann::json writeModel(const model::DhChainSpec& spec);

/// The file format's name of an interpolation kind: "linear", "quadratic" or "cubic".
const char* interpolationName(model::Interpolation interpolation) noexcept;

/// Factor from a length unit name (mm|um|nm) to mm; angle unit name (rad|mrad|urad|arcsec|deg) to
/// rad, for unit names read from other files (CSV column units). Throw ConfigError with the given
/// file/path on an unknown name.
double lengthUnitToMm(const std::string& unit, const std::string& file, const std::string& path);
double angleUnitToRad(const std::string& unit, const std::string& file, const std::string& path);
/// The same factors without throwing: nullopt for a name that is not one of those units.
std::optional<double> lengthUnitFactor(std::string_view unit) noexcept;
std::optional<double> angleUnitFactor(std::string_view unit) noexcept;

}  // namespace volcomp::config
