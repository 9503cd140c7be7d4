#pragma once
/// Hanak, Zirn and Ruoff's planar 2-DOF device as files (docs/calibration.md): the device file
/// ("format": "volcomp-planar2dof/1"; lengths mm, phi in degrees), the readings CSV (a, b, gx, gy,
/// mm unless a unit suffix says), and its calibration against the lattice grid plate with the
/// paper's figures of merit. The maths is planar2dof.hpp's.

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/calibration/calibrate.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"
#include "volcomp/calibration/planar2dof.hpp"

namespace volcomp::calibration {

/// True for a document whose "format" is "volcomp-planar2dof/1".
bool isPlanar2DofDocument(const nlohmann::json& document);

/// A device file, in internal units (mm, rad).
struct Planar2DofDevice {
  Planar2DofGeometry geometry;
  /// Which parameters the fit identifies ("free"; the paper's seven by default).
  std::array<bool, kPlanar2DofParameterCount> free = kPaperFreeParameters;
  /// Start values of the free parameters and the values of the fixed ones (0 unless given).
  Planar2DofParameters start{};
  /// 1-based number of the reading that is the common origin (the paper's n = 1).
  int referencePoint = 1;
};

/// Reads a device document; throws config::ConfigError naming `file` and the key.
Planar2DofDevice readPlanar2DofDevice(const nlohmann::json& document, const std::string& file);

/// The readings a, b (scale readings, mm) and gx, gy (grid plate, mm) with their CSV lines.
struct Planar2DofReadings {
  std::vector<Planar2DofSample> samples;
  std::vector<int> lines;
};

/// Reads a readings CSV (config::CsvReader); throws config::ConfigError naming the file, line and
/// column, and for fewer than 2 readings.
Planar2DofReadings readPlanar2DofReadings(const std::string& path);

struct Planar2DofCalibration {
  /// The free parameters in the units of Hanak, Zirn and Ruoff's table 2: lengths mm, phi deg, exK and eyK um.
  std::vector<ParameterInfo> parameters;
  FitResult fit;
  /// Hanak, Zirn and Ruoff's s_r: the standard deviation of the computed position through all parameter
  /// variances and covariances, |sigma| of the 2-D vector, RMS over the points (mm).
  double positionStdMm = 0.0;
  /// Mean length of the 2-D deviations |dL_i| between device and grid plate (mm).
  double meanDeviationBeforeMm = 0.0;
  double meanDeviationAfterMm = 0.0;
  /// The device document with "values" (all nine) and "std" (the free ones; null where not
  /// identifiable), in the file's units (mm, phi in degrees).
  nlohmann::json fittedDevice;
};

/// Fits the device with Levenberg-Marquardt (settings: rankTolerance, maxIterations). `document`
/// is the device file the fitted device is written from; `file` names it in errors (a reference
/// point beyond the readings: config::ConfigError at "reference_point").
Planar2DofCalibration calibratePlanar2Dof(const nlohmann::json& document, const std::string& file,
                                          const Planar2DofDevice& device,
                                          const Planar2DofReadings& readings,
                                          const CalibrationSettings& settings);

}  // namespace volcomp::calibration
