#pragma once
/// The daemon's composition from plain structs: the configuration file (config::DaemonConfig)
/// becomes the loop's settings and the model file a CompensationModel. Never on the hot path.

#include <memory>
#include <string>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/model_plausibility.hpp"
#include "volcomp/loop/compensation_model.hpp"
#include "volcomp/loop/loop_settings.hpp"

namespace volcomp::daemon {

/// A validated configuration with its model.
struct LoadedConfiguration {
  config::DaemonConfig config;
  std::shared_ptr<loop::CompensationModel> model;
};

/// Reads the daemon configuration (its transport section into the driver's settings) and the
/// model it names. Throws config::ConfigError (file, key path, what was expected).
LoadedConfiguration loadConfiguration(const std::string& configPath);

/// Loads and validates a model file for the daemon (3-axis machine models only; a D-H chain is
/// rejected), including the plausibility check over its travel (config/model_plausibility.hpp)
/// and, when `bound` is given, that its offsets fit the limiter. Throws config::ConfigError
/// (file, key path, what was expected).
std::shared_ptr<loop::CompensationModel> loadCompensationModel(
    const std::string& path, const std::optional<config::OffsetBound>& bound = std::nullopt);

/// The loop's settings (durations, mm) from the configuration file's values (ms, mm).
loop::LoopSettings loopSettingsFrom(const config::DaemonConfig& config) noexcept;

}  // namespace volcomp::daemon
