#pragma once
// What `volcompd --check-config` checks beyond the files: that the transport's endpoint exists on
// this machine now (a TCP host that resolves, a serial device, a CAN interface).

#include <string>

#include "volcomp/config/transport_config.hpp"

namespace volcomp::volcompd {

/// Throws config::ConfigError naming `file`, the transport key and what to do when the host does
/// not resolve, the serial device does not exist, or the CAN interface does not exist (with the
/// commands that create it). Returns a one-line description of what was found.
std::string checkTransportEnvironment(const config::TransportSettings& settings,
                                      const std::string& file);

}  // namespace volcomp::volcompd
