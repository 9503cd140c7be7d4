#pragma once
// volcompd's composition root for drivers: the transport section's typed settings become the
// driver that implements the loop's ControllerPort.

#include <memory>
#include <string>

#include "volcomp/config/transport_config.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::volcompd {

/// The unconnected port for `settings`: the libmodbus port for Modbus TCP/RTU, the SocketCAN port
/// for CAN, the HAL component for LinuxCNC. Throws config::ConfigError naming `file` at "transport"
/// when libmodbus refuses settings that passed validation.
std::unique_ptr<loop::ControllerPort> makeControllerPort(const config::TransportSettings& settings,
                                                         const std::string& file);

}  // namespace volcomp::volcompd
