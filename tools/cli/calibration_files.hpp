#pragma once
// Shared by `volcomp calibrate` and `volcomp plan`: the screen's angle unit from its option text,
// the run's time stamp, and JSON result files written through volcomp::output.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/calibration/report.hpp"

namespace volcomp::cli {

/// Option errors are reported like file errors ("command line: --loss: ..."), exit status 2.
inline constexpr const char* kCommandLine = "command line";

/// "urad" or "arcsec"; throws config::ConfigError naming --angle-unit otherwise.
calibration::AngleDisplay angleDisplayFromText(const std::string& text);

/// Now as ISO 8601 UTC, e.g. "2026-12-01T19:40:00Z".
std::string utcNow();

/// Written whole or not at all, never over one of `inputs` (output::writeOutputFile).
void writeJsonFile(const std::string& path, const nlohmann::json& document,
                   const std::vector<std::filesystem::path>& inputs);

}  // namespace volcomp::cli
