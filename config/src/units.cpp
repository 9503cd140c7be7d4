#include <array>
#include <numbers>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

struct LengthUnitInfo {
  LengthUnit unit;
  const char* name;
  double toMm;
};

struct AngleUnitInfo {
  AngleUnit unit;
  const char* name;
  double toRad;
};

// In enum order: the tables are indexed by the enum's value.
constexpr std::array<LengthUnitInfo, 3> kLengthUnits{{
    {LengthUnit::Millimetre, "mm", 1.0},
    {LengthUnit::Micrometre, "um", 1e-3},
    {LengthUnit::Nanometre, "nm", 1e-6},
}};

constexpr std::array<AngleUnitInfo, 5> kAngleUnits{{
    {AngleUnit::Radian, "rad", 1.0},
    {AngleUnit::Milliradian, "mrad", 1e-3},
    {AngleUnit::Microradian, "urad", 1e-6},
    {AngleUnit::Arcsecond, "arcsec", std::numbers::pi / 648000.0},
    {AngleUnit::Degree, "deg", std::numbers::pi / 180.0},
}};

const LengthUnitInfo& info(LengthUnit unit) noexcept {
  return kLengthUnits[static_cast<std::size_t>(unit)];
}

const AngleUnitInfo& info(AngleUnit unit) noexcept {
  return kAngleUnits[static_cast<std::size_t>(unit)];
}

}  // namespace

const char* unitName(LengthUnit unit) noexcept {
  return info(unit).name;
}
const char* unitName(AngleUnit unit) noexcept {
  return info(unit).name;
}
double toMm(LengthUnit unit) noexcept {
  return info(unit).toMm;
}
double toRad(AngleUnit unit) noexcept {
  return info(unit).toRad;
}

std::optional<LengthUnit> lengthUnitFromName(std::string_view name) noexcept {
  for (const LengthUnitInfo& u : kLengthUnits) {
    if (name == u.name) return u.unit;
  }
  return std::nullopt;
}

std::optional<AngleUnit> angleUnitFromName(std::string_view name) noexcept {
  for (const AngleUnitInfo& u : kAngleUnits) {
    if (name == u.name) return u.unit;
  }
  return std::nullopt;
}

std::optional<double> lengthUnitFactor(std::string_view unit) noexcept {
  if (const std::optional<LengthUnit> u = lengthUnitFromName(unit)) return toMm(*u);
  return std::nullopt;
}

std::optional<double> angleUnitFactor(std::string_view unit) noexcept {
  if (const std::optional<AngleUnit> u = angleUnitFromName(unit)) return toRad(*u);
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
