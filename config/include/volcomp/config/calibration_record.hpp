#pragma once
/// The optional "calibration" block of a model file: where an identified model comes from
/// (written by `volcomp calibrate`, kept by whoever copies the file) and the tool offsets it was
/// measured with. Nothing in it changes a single evaluated number.
///
/// ```json
/// "calibration": {
///   "volcomp_version": "0.1.0", "date": "2026-12-01T19:40:00Z",
///   "template": "vmc-template.json", "measurements": ["tracer.csv"], "validation": "check.csv",
///   "points": 8316, "parameter_count": 125, "rank": 122,
///   "residual_rms_mm": {"before": 0.0158, "after": 0.00086, "validation": 0.00091},
///   "s0_mm": 0.0005,
///   "not_identifiable": ["EAX[0]", "EAY[0]"],
///   "tools_mm": [[0, 0, 120], [0, 0, 220]]
/// }
/// ```
/// Every key is optional. `not_identifiable` names the parameters (as in the calibration report)
/// that the data did not determine: their values in the file are the start values plus the
/// minimum-norm change, not measured values. `tools_mm` are the distinct tool offsets (mm) of
/// the measurements: errors that depend on the tool (through the angular errors' lever arms) are
/// measured for those and interpolated between them; toolDistanceMm() says how far outside them
/// a tool is.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {

struct CalibrationRecord {
  std::string volcompVersion;
  std::string date;  ///< ISO 8601, UTC
  std::string templateFile;
  std::vector<std::string> measurementFiles;
  std::string validationFile;
  std::optional<int> points;
  std::optional<int> parameterCount;
  std::optional<int> rank;
  std::optional<double> residualRmsBeforeMm;
  std::optional<double> residualRmsAfterMm;
  std::optional<double> residualRmsValidationMm;
  std::optional<double> s0Mm;
  std::vector<std::string> notIdentifiable;
  std::vector<Eigen::Vector3d> toolsMm;
};

/// Reads the block (key path of `node`, e.g. "calibration"); throws ConfigError on a wrong type
/// or an unknown key.
CalibrationRecord readCalibrationRecord(const JsonReader& node);
/// Writes the block (keys with no value are left out).
nlohmann::json writeCalibrationRecord(const CalibrationRecord& record);

/// A tool offset further than this outside the calibrated tools is worth a warning: over 10 mm an
/// angular error of 100 urad (a typical pitch or yaw) already makes 1 um, the size of a good
/// calibration's residual.
inline constexpr double kCalibratedToolToleranceMm = 10.0;

/// Distance (mm) from `toolMm` to the convex hull of the calibrated tools (0 inside it, e.g.
/// between two measured tool lengths; the distance to the single tool when one was measured).
/// std::nullopt when the record lists no tools. The predicted error is affine in the tool offset,
/// so inside the hull it is an interpolation of what was measured, outside an extrapolation.
std::optional<double> toolDistanceMm(const CalibrationRecord& record,
                                     const Eigen::Vector3d& toolMm);

}  // namespace volcomp::config
