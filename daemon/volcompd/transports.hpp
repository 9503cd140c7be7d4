#pragma once
// volcompd's composition root for drivers: the transport section's typed settings become the
// driver that implements the loop's ControllerPort.

#include <functional>
#include <memory>
#include <string>

#include "volcomp/config/transport_config.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::volcompd {

/// The unconnected port for `settings`: the libmodbus port for Modbus TCP/RTU, the SocketCAN port
/// for CAN, the HAL component for LinuxCNC (volcompd-linuxcnc; plain volcompd refuses it, see
/// program.hpp). Throws config::ConfigError naming `file` at "transport" when libmodbus refuses
/// settings that passed validation.
std::unique_ptr<loop::ControllerPort> makeControllerPort(const config::TransportSettings& settings,
                                                         const std::string& file);

/// With the Modbus server role and cycle_trigger "write": each complete position set the master
/// writes calls `runCycle` on the server's service thread (which must hand it to the io_context).
/// Does nothing for any other port.
void connectCycleTrigger(loop::ControllerPort& port, std::function<void()> runCycle);

}  // namespace volcomp::volcompd
