#include "volcomp/config/transport_config.hpp"

#include "volcomp/config/can_config.hpp"
#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/linuxcnc_config.hpp"
#include "volcomp/config/modbus_config.hpp"

namespace volcomp::config {

TransportSettings parseTransportSettings(const nlohmann::json& section, const std::string& file,
                                         const std::string& keyPath) {
  const JsonReader transport(section, file, keyPath);
  transport.expectObject();
  const std::string type =
      transport.at("type").oneOf({"modbus-tcp", "modbus-rtu", "can", "linuxcnc"});
  if (type == "can") return loadCanLayout(section, file, keyPath);
  if (type == "linuxcnc") return parseLinuxCncSettings(section, file, keyPath);
  return parseModbusSettings(section, file, keyPath);
}

std::string transportType(const TransportSettings& settings) {
  if (const auto* modbus = std::get_if<modbus::ModbusSettings>(&settings)) {
    return std::holds_alternative<modbus::RtuLink>(modbus->link) ? "modbus-rtu" : "modbus-tcp";
  }
  if (std::holds_alternative<can::CanLayout>(settings)) return "can";
  return "linuxcnc";
}

}  // namespace volcomp::config
