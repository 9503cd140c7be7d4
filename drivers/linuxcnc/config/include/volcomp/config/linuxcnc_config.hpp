#pragma once
/// The LinuxCNC transport section of a daemon configuration, read into linuxcnc::HalSettings.
///
/// JSON shape (key paths relative to the section):
///   {
///     "type": "linuxcnc",
///     "component": "volcomp",     optional: HAL component name and signal prefix; letters,
///                                 digits, '_' and '-', at most 26 characters (HAL names are
///                                 at most 47 with the longest pin suffix)
///     "counts_per_mm": 10000      optional: eoffset-counts per mm, in [1, 1e7]
///   }

#include <string>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/linuxcnc/settings.hpp"

namespace volcomp::config {

/// Parses and validates a LinuxCNC transport section. Throws ConfigError naming `file` and the
/// key path under `keyPath`.
linuxcnc::HalSettings parseLinuxCncSettings(const nlohmann::json& section, const std::string& file,
                                            const std::string& keyPath);

}  // namespace volcomp::config
