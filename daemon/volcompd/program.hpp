#pragma once
// What differs between the two builds of the daemon: plain volcompd (Modbus and CAN) and
// volcompd-linuxcnc (the same daemon plus LinuxCNC's HAL transport, linked to liblinuxcnchal).
// Everything else (main, commissioning, probe, environment check, the other drivers) is shared;
// each program links exactly one of without_linuxcnc.cpp and with_linuxcnc.cpp.

#include <memory>
#include <string>

#include "volcomp/config/transport_config.hpp"
#include "volcomp/linuxcnc/settings.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::volcompd {

/// The program's name, as --version and --help print it: "volcompd" or "volcompd-linuxcnc".
extern const char* const kProgramName;

/// Throws config::ConfigError naming `file` at "transport.type" when this program has no driver
/// for the transport section (plain volcompd given a "linuxcnc" section: the message names
/// volcompd-linuxcnc and its package). Returns when it has one.
void requireTransportBuiltIn(const config::TransportSettings& settings, const std::string& file);

/// The unconnected HAL component port of volcompd-linuxcnc; plain volcompd throws the
/// config::ConfigError of requireTransportBuiltIn.
std::unique_ptr<loop::ControllerPort> makeLinuxCncPort(const linuxcnc::HalSettings& settings,
                                                       const std::string& file);

}  // namespace volcomp::volcompd
