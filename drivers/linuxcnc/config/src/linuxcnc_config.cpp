#include "volcomp/config/linuxcnc_config.hpp"

#include <algorithm>
#include <cctype>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {
namespace {

// HAL names are at most 47 characters: "<component>-16.x.eoffset-request" must fit.
constexpr std::size_t kMaxComponentName = 26;

}  // namespace

linuxcnc::HalSettings parseLinuxCncSettings(const nlohmann::json& section, const std::string& file,
                                            const std::string& keyPath) {
  const JsonReader r(section, file, keyPath);
  r.expectObject();
  r.allowOnly({"type", "component", "counts_per_mm"});
  r.at("type").oneOf({"linuxcnc"});
  linuxcnc::HalSettings s;
  if (auto c = r.find("component")) {
    s.component = c->string();
    const bool valid = !s.component.empty() && s.component.size() <= kMaxComponentName &&
                       std::all_of(s.component.begin(), s.component.end(), [](unsigned char ch) {
                         return std::isalnum(ch) != 0 || ch == '_' || ch == '-';
                       });
    if (!valid) {
      c->failExpected("a HAL component name of 1 to " + std::to_string(kMaxComponentName) +
                      " letters, digits, '_' or '-'");
    }
  }
  if (auto c = r.find("counts_per_mm")) s.countsPerMm = c->number(1.0, 1e7);
  return s;
}

}  // namespace volcomp::config
