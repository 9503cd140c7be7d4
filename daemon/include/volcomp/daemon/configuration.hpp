#pragma once
/// The daemon's composition from plain structs: the configuration file (config::DaemonConfig)
/// becomes the loop's settings and the model file a CompensationModel. Never on the hot path.

#include <memory>
#include <string>
#include <vector>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/model_plausibility.hpp"
#include "volcomp/loop/compensation_model.hpp"
#include "volcomp/loop/loop_settings.hpp"

namespace volcomp::daemon {

/// A validated configuration with its model.
struct LoadedConfiguration {
  config::DaemonConfig config;
  std::shared_ptr<loop::CompensationModel> model;
  /// What the daemon logs as warnings when it starts or reloads with this model (e.g. a tool far
  /// outside the tools the model was calibrated with).
  std::vector<std::string> warnings;
};

/// Reads the daemon configuration (its transport section into the driver's settings) and the
/// model it names. Throws config::ConfigError (file, key path, what was expected).
LoadedConfiguration loadConfiguration(const std::string& configPath);

/// Loads and validates a model file for the daemon (3-axis machine models only; a D-H chain is
/// rejected), including the plausibility check over its travel (config/model_plausibility.hpp)
/// and, when `bound` is given, that its offsets fit the limiter. Throws config::ConfigError
/// (file, key path, what was expected). When `warnings` is given, what is worth a warning about
/// the model is appended to it: a tool more than config::kCalibratedToolToleranceMm outside the tool offsets recorded in the model's
/// "calibration" block (the errors acting through the tool's lever arms are then extrapolated).
std::shared_ptr<loop::CompensationModel> loadCompensationModel(
    const std::string& path, const std::optional<config::OffsetBound>& bound = std::nullopt,
    std::vector<std::string>* warnings = nullptr);

/// The loop's settings (durations, mm) from the configuration file's values (ms, mm).
loop::LoopSettings loopSettingsFrom(const config::DaemonConfig& config) noexcept;

}  // namespace volcomp::daemon
