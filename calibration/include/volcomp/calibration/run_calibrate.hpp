#pragma once
/// `volcomp calibrate TEMPLATE.json MEASUREMENTS.csv --out MODEL.json [--report REPORT.json]`:
/// the whole verb behind the CLI's argument parsing (the CLI maps exceptions to exit codes).

#include <iosfwd>
#include <optional>
#include <string>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

struct CalibrateOptions {
  std::string templatePath;
  std::string measurementsPath;
  std::string outPath;
  std::string reportPath;  ///< empty: no JSON report file
  /// "auto" (linear for 3-axis models without robust loss, Levenberg-Marquardt otherwise),
  /// "linear" or "lm".
  std::string method = "auto";
  /// "none", "huber" or "cauchy", with lossScaleMm.
  std::string loss = "none";
  double lossScaleMm = 0.01;
  double rankTolerance = 1e-7;
  int maxIterations = 100;
  IdentificationOptions identification;
  /// Write the model even when the data identify fewer than half of the parameters.
  bool force = false;
  /// Held-out measurements (same CSV format) whose residuals are reported beside the fit's.
  std::string validatePath;
  /// k > 1: k-fold cross-validation of the measurements (k more fits).
  int folds = 0;
  /// Points (CSV: x,y,z [,tx,ty,tz] [,direction]) at which to predict the error with its
  /// uncertainty, written to predictOutPath (and listed in the report).
  std::string predictPath;
  std::string predictOutPath;
  /// Screen unit of angles: "urad" or "arcsec".
  std::string angleUnit = "urad";
  /// Recorded in the model's "calibration" block and the report.
  std::string volcompVersion = "unknown";
};

/// Runs the calibration: progress and the summary go to `out`. Returns 0 on success (also when
/// the data leave parameters unidentifiable: that is reported, not an error). Throws
/// config::ConfigError for bad files and for bad option values (file "command line", key the
/// option), which the CLI reports as exit status 2; also when the data identify fewer than half
/// of the parameters and `force` is not set (then a summary of what is missing is on `out` and
/// nothing is written).
///
/// A template whose "format" is "volcomp-planar2dof/1" calibrates seed 003's planar device
/// (see planar2dof_run.hpp).
int runCalibrate(const CalibrateOptions& options, std::ostream& out);

}  // namespace volcomp::calibration
