#pragma once
/// Driver factories by transport type ("modbus-tcp", "modbus-rtu", "can"), so that volcompd picks
/// the driver named in the configuration and builds with whichever drivers are available.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::daemon {

/// Builds an unconnected port from the "transport" section; key paths in its ConfigErrors start
/// at "transport". Throws config::ConfigError.
using PortFactory = std::function<std::unique_ptr<loop::ControllerPort>(
    const nlohmann::json& transportSection, const std::string& file)>;

class TransportRegistry {
 public:
  void add(const std::string& type, PortFactory factory);
  bool has(const std::string& type) const { return factories_.count(type) != 0; }
  std::vector<std::string> types() const;
  /// The port for config.transportType. Throws ConfigError at "transport.type" when no driver for
  /// that type was built into this executable, or whatever the driver's parser throws.
  std::unique_ptr<loop::ControllerPort> create(const config::DaemonConfig& config) const;

 private:
  std::map<std::string, PortFactory> factories_;
};

}  // namespace volcomp::daemon
