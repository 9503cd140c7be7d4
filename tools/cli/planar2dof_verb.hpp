#pragma once
// `volcomp calibrate DEVICE.json READINGS.csv` for Hanak, Zirn and Ruoff's planar 2-DOF device (a template
// with "format": "volcomp-planar2dof/1"; docs/calibration.md describes the files).

#include <iosfwd>

#include <nlohmann/json.hpp>

#include "calibrate_verb.hpp"

namespace volcomp::cli {

/// Fits the device, prints the paper's table 2 layout (start, optimised value and sigma per
/// parameter), the correlations, s_r and the mean deviations, writes the device file with the
/// identified values (--out) and the report (--report). Options are checked by runCalibrate.
int runPlanar2Dof(const nlohmann::json& document, const CalibrateOptions& options,
                  std::ostream& out);

}  // namespace volcomp::cli
