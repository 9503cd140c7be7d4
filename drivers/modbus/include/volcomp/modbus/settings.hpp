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
  /// Simultaneous TCP connections. When all are taken, a new connection from an allowed client
  /// replaces the one silent longest if that one has sent no request for takeoverAfterMs;
  /// otherwise the new one is closed at once.
  int maxConnections = 1;
  /// A connection that sends no request for this long is closed, s (0 = never).
  int idleTimeoutS = 60;
  /// TCP keepalive: probes start after this many seconds of silence from the peer and repeat at
  /// the same interval; 3 unanswered probes close the connection (a peer that lost power or
  /// rebooted without closing it). 0 = off.
  int keepaliveS = 10;
  /// Silence after which a connection gives its slot to a new one when all slots are taken, ms.
  int takeoverAfterMs = 1000;
  CycleTrigger trigger = CycleTrigger::Write;
  bool operator==(const ServerSettings&) const = default;
};

struct ModbusSettings {
  ModbusRole role = ModbusRole::Client;
  ServerSettings server;  ///< used with role Server only
  std::variant<TcpLink, RtuLink> link;
  int slaveId = 1;
  /// Maximum wait for a response to one transaction (and between bytes of a response), ms. In the
  /// server role: the longest a request may take to arrive, first byte to last (TCP: a slower
  /// sender is disconnected; RTU: the byte timeout).
  double responseTimeoutMs = 50.0;
  /// This many consecutive response timeouts mean the link is gone: the driver closes it and
  /// reports not_connected, so that the loop reconnects.
  int linkLossTimeouts = 3;
  RegisterMap registers;
  bool operator==(const ModbusSettings&) const = default;
};

}  // namespace volcomp::modbus
