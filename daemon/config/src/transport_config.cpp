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

std::string transportEndpoint(const TransportSettings& settings) {
  if (const auto* modbus = std::get_if<modbus::ModbusSettings>(&settings)) {
    const bool server = modbus->role == modbus::ModbusRole::Server;
    if (const auto* tcp = std::get_if<modbus::TcpLink>(&modbus->link)) {
      if (server) {
        return "modbus-tcp server " + modbus->server.listenAddress + ":" +
               std::to_string(tcp->port);
      }
      const bool v6 = tcp->host.find(':') != std::string::npos;
      return "modbus-tcp " + (v6 ? "[" + tcp->host + "]" : tcp->host) + ":" +
             std::to_string(tcp->port);
    }
    const auto& rtu = std::get<modbus::RtuLink>(modbus->link);
    return std::string(server ? "modbus-rtu server " : "modbus-rtu ") + rtu.device + " (" +
           std::to_string(rtu.baud) + " " + std::to_string(rtu.dataBits) + rtu.parity +
           std::to_string(rtu.stopBits) + ", slave " + std::to_string(modbus->slaveId) + ")";
  }
  if (const auto* can = std::get_if<can::CanLayout>(&settings)) return "can " + can->interfaceName;
  return transportType(settings);
}

}  // namespace volcomp::config
