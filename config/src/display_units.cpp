#include "volcomp/config/display_units.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "volcomp/format/numbers.hpp"

namespace volcomp::config {

std::string significant(double value) {
  if (!std::isfinite(value)) return value != value ? "nan" : (value > 0 ? "inf" : "-inf");
  std::string text = format::fixedSignificant(value, 4, 3);
  // Trailing zeros say nothing about precision here: "15.60" -> "15.6", "250.0" -> "250".
  if (text.find('.') != std::string::npos) {
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
  }
  // "-0.000" is a rounded zero: no sign on it.
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

std::string micrometres(double mm) {
  return significant(mm * 1000.0) + " um";
}

AngleDisplay angleDisplayFromName(std::string_view name) {
  if (name == "urad") return AngleDisplay::Microradian;
  if (name == "arcsec") return AngleDisplay::Arcsecond;
  throw std::invalid_argument("expected an angle unit \"urad\" or \"arcsec\", got \"" +
                              std::string(name) + "\"");
}

std::string angle(double rad, AngleDisplay display) {
  if (display == AngleDisplay::Arcsecond) {
    return significant(rad * 648000.0 / std::numbers::pi) + " arcsec";
  }
  return significant(rad * 1e6) + " urad";
}

}  // namespace volcomp::config
