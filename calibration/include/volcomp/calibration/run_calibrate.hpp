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
};

/// Runs the calibration: progress and the summary go to `out`. Returns 0 on success (also when
/// the data leave parameters unidentifiable: that is reported, not an error). Throws
/// config::ConfigError for bad files and for bad option values (file "command line", key the
/// option), which the CLI reports as exit status 2.
int runCalibrate(const CalibrateOptions& options, std::ostream& out);

}  // namespace volcomp::calibration
