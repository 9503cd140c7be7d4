#pragma once
// `volcomp calibrate TEMPLATE.json MEASUREMENTS.csv --out MODEL.json [--report REPORT.json]`:
// the options, the run (files read, volcomp::calibration's steps, the summary printed, the model,
// report and predictions written) and, for a "volcomp-planar2dof/1" device file, Hanak, Zirn and Ruoff's
// device (planar2dof_verb.hpp).

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

#include "volcomp/calibration/calibrate.hpp"
#include "volcomp/calibration/report.hpp"

namespace volcomp::cli {

struct CalibrateOptions {
  std::string templatePath;
  std::string measurementsPath;
  std::string outPath;
  std::string reportPath;  ///< empty: no JSON report file
  calibration::CalibrationSettings settings;
  /// Write the model even when the data identify fewer than half of the parameters.
  bool force = false;
  /// Held-out measurements (same CSV format) whose residuals are reported beside the fit's.
  std::string validatePath;
  /// Points (CSV: x,y,z [,tx,ty,tz] [,direction]) at which to predict the error with its
  /// uncertainty, written to predictOutPath (and listed in the report).
  std::string predictPath;
  std::string predictOutPath;
  calibration::AngleDisplay angleDisplay = calibration::AngleDisplay::Microradian;
  /// Recorded in the model's "calibration" block and the report.
  std::string volcompVersion = "unknown";
};

/// The options as given on the command line; the choices are text until resolved.
struct CalibrateArguments {
  CalibrateOptions options;
  std::string method = "auto";  ///< auto, linear or lm
  std::string loss = "none";    ///< none, huber or cauchy
  std::string angleUnit = "urad";
};

CLI::App* addCalibrateVerb(CLI::App& app, CalibrateArguments& arguments);

/// Maps the text options to arguments.options' choices; throws config::ConfigError (file
/// "command line", key the option) for text that names none.
void resolveCalibrateArguments(CalibrateArguments& arguments);

/// Runs the calibration: progress and the summary go to `out`. Returns 0 on success (also when
/// the data leave parameters unidentifiable: that is reported, not an error). Throws
/// config::ConfigError for bad files and for bad option values (file "command line", key the
/// option), which main() reports as exit status 2; also when the data identify fewer than half
/// of the parameters and `force` is not set (then a summary of what is missing is on `out` and
/// nothing is written).
int runCalibrate(const CalibrateOptions& options, std::ostream& out);

}  // namespace volcomp::cli
