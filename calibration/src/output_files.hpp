#pragma once
// Internal: writing result files and stamping them (shared by the calibrate flows).

#include <chrono>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/output/output_file.hpp"

namespace volcomp::calibration::detail {

/// Written whole or not at all, never over one of `inputs` (output::writeOutputFile).
inline void writeJsonFile(const std::string& path, const nlohmann::json& document,
                          const std::vector<std::filesystem::path>& inputs) {
  output::writeOutputFile(path, document.dump(2) + '\n', inputs);
}

/// Now as ISO 8601 UTC, e.g. "2026-12-01T19:40:00Z".
inline std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

}  // namespace volcomp::calibration::detail
