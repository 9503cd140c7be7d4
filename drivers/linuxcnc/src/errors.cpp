#include "volcomp/linuxcnc/errors.hpp"

#include <string>

namespace volcomp::linuxcnc {
namespace {

class HalCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "linuxcnc-hal"; }
  std::string message(int value) const override {
    switch (static_cast<HalErrc>(value)) {
      case HalErrc::hal_call_failed:
        return "LinuxCNC's HAL refused a call";
      case HalErrc::component_in_use:
        return "the HAL component belongs to another running volcompd";
      case HalErrc::missing_signal:
        return "a required HAL signal is not declared";
      case HalErrc::link_failed:
        return "a HAL pin could not join its signal";
    }
    return "unknown LinuxCNC HAL error";
  }
};

}  // namespace

const std::error_category& halCategory() noexcept {
  static const HalCategory category;
  return category;
}

}  // namespace volcomp::linuxcnc
