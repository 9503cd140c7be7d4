// Plain volcompd: Modbus and CAN. A "linuxcnc" transport section is read and validated like any
// other, then refused with the program that has the HAL transport.
#include <variant>

#include "program.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::volcompd {

const char* const kProgramName = "volcompd";

void requireTransportBuiltIn(const config::TransportSettings& settings, const std::string& file) {
  if (std::holds_alternative<linuxcnc::HalSettings>(settings)) {
    throw config::ConfigError(
        file, "transport.type",
        "\"linuxcnc\" is the transport of volcompd-linuxcnc (package volcomp-linuxcnc); this "
        "volcompd has the modbus-tcp, modbus-rtu and can transports");
  }
}

std::unique_ptr<loop::ControllerPort> makeLinuxCncPort(const linuxcnc::HalSettings& settings,
                                                       const std::string& file) {
  requireTransportBuiltIn(settings, file);
  return nullptr;
}

}  // namespace volcomp::volcompd
