#include <numbers>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {

std::optional<double> lengthUnitFactor(std::string_view unit) noexcept {
  if (unit == "mm") return 1.0;
  if (unit == "um") return 1e-3;
  if (unit == "nm") return 1e-6;
  return std::nullopt;
}

std::optional<double> angleUnitFactor(std::string_view unit) noexcept {
  if (unit == "rad") return 1.0;
  if (unit == "mrad") return 1e-3;
  if (unit == "urad") return 1e-6;
  if (unit == "arcsec") return std::numbers::pi / 648000.0;
  if (unit == "deg") return std::numbers::pi / 180.0;
  return std::nullopt;
}

double lengthUnitToMm(const std::string& unit, const std::string& file, const std::string& path) {
  if (const std::optional<double> factor = lengthUnitFactor(unit)) return *factor;
  throw ConfigError(file, path,
                    "expected a length unit \"mm\", \"um\" or \"nm\", got \"" + unit + "\"");
}

double angleUnitToRad(const std::string& unit, const std::string& file, const std::string& path) {
  if (const std::optional<double> factor = angleUnitFactor(unit)) return *factor;
  throw ConfigError(
      file, path,
      "expected an angle unit \"rad\", \"mrad\", \"urad\", \"arcsec\" or \"deg\", got \"" + unit +
          "\"");
}

}  // namespace volcomp::config
