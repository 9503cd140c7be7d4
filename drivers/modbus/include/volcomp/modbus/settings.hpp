#pragma once
/// Everything the Modbus client driver needs to reach a controller: the link (TCP or RTU), the
/// slave id, timeouts and the register map. Plain data (config/modbus_config.hpp reads it from a
/// transport section).

#include <cstdint>
#include <string>
#include <variant>

#include "volcomp/modbus/registers.hpp"

namespace volcomp::modbus {

struct TcpLink {
  std::string host = "127.0.0.1";
  std::uint16_t port = 502;
  bool operator==(const TcpLink&) const = default;
};

struct RtuLink {
  std::string device;
  int baud = 115200;
  char parity = 'N';  ///< 'N', 'E' or 'O'
  int dataBits = 8;
  int stopBits = 1;
  bool operator==(const RtuLink&) const = default;
};

struct ModbusSettings {
  std::variant<TcpLink, RtuLink> link;
  int slaveId = 1;
  /// Maximum wait for a response to one transaction (and between bytes of a response), ms.
  double responseTimeoutMs = 50.0;
  /// This many consecutive response timeouts mean the link is gone: the driver closes it and
  /// reports not_connected, so that the loop reconnects.
  int linkLossTimeouts = 3;
  RegisterMap registers;
  bool operator==(const ModbusSettings&) const = default;
};

}  // namespace volcomp::modbus
