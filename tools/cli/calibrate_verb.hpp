#pragma once
// `volcomp calibrate TEMPLATE.json MEASUREMENTS.csv --out MODEL.json [--report REPORT.json]`:
// argument parsing only; the work is volcomp::calibration::runCalibrate.

#include <CLI/App.hpp>

#include "volcomp/calibration/run_calibrate.hpp"

namespace volcomp::cli {

CLI::App* addCalibrateVerb(CLI::App& app, calibration::CalibrateOptions& options);

}  // namespace volcomp::cli
