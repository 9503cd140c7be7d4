#pragma once
/// Everything the Modbus client driver needs to reach a controller: the link (TCP or RTU), the
/// slave id, timeouts and the register map. Plain data (config/modbus_config.hpp reads it from a
/// transport section).

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

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

/// Which end of the link volcompd is: the client polls the controller (a PLC that is a server);
/// the server holds the register bank that a controller acting as master (Siemens MB_CLIENT,
/// Beckhoff TF6250, Codesys, LinuxCNC's mb2hal) writes and reads.
enum class ModbusRole : std::uint8_t { Client, Server };

/// Server role: what starts a loop cycle. `Write`: each complete position set the master writes
/// (with a fallback cycle on the period timer when none came for one period); `Timer`: the
/// period timer alone, whatever the master writes.
enum class CycleTrigger : std::uint8_t { Write, Timer };

/// Server-role settings. TCP: the listening address and port come from `listenAddress` and
/// TcpLink::port (0 = any free port, logged); RTU: the device of RtuLink is opened as the slave.
struct ServerSettings {
  std::string listenAddress = "127.0.0.1";  ///< IPv4 address to bind (TCP)
  /// IPv4 addresses (network byte order) allowed to connect; empty = any (TCP).
  std::vector<std::uint32_t> allowedClients;
  int maxConnections = 1;  ///< simultaneous TCP connections; a further one is closed at once
  CycleTrigger trigger = CycleTrigger::Write;
  bool operator==(const ServerSettings&) const = default;
};

struct ModbusSettings {
  ModbusRole role = ModbusRole::Client;
  ServerSettings server;  ///< used with role Server only
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
