#include "calibration_files.hpp"

#include <chrono>
#include <ctime>

#include "volcomp/config/config_error.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {

calibration::AngleDisplay angleDisplayFromText(const std::string& text) {
  if (text == "urad") return calibration::AngleDisplay::Microradian;
  if (text == "arcsec") return calibration::AngleDisplay::Arcsecond;
  throw config::ConfigError(kCommandLine, "--angle-unit", "expected urad or arcsec");
}

std::string utcNow() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

void writeJsonFile(const std::string& path, const nlohmann::json& document,
                   const std::vector<std::filesystem::path>& inputs) {
  output::writeOutputFile(path, document.dump(2) + '\n', inputs);
}

}  // namespace volcomp::cli
