#include "volcomp/daemon/transport_registry.hpp"

#include <utility>

#include "volcomp/config/config_error.hpp"

namespace volcomp::daemon {

void TransportRegistry::add(const std::string& type, PortFactory factory) {
  factories_[type] = std::move(factory);
}

std::vector<std::string> TransportRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& [type, factory] : factories_) out.push_back(type);
  return out;
}

std::unique_ptr<loop::ControllerPort> TransportRegistry::create(
    const config::DaemonConfig& config) const {
  const auto it = factories_.find(config.transportType);
  if (it == factories_.end()) {
    std::string available;
    for (const auto& [type, factory] : factories_) {
      available += available.empty() ? "" : ", ";
      available += type;
    }
    throw config::ConfigError(config.file, "transport.type",
                              "no driver for \"" + config.transportType +
                                  "\" is built into this volcompd (available: " +
                                  (available.empty() ? std::string("none") : available) + ")");
  }
  std::unique_ptr<loop::ControllerPort> port = it->second(config.transport, config.file);
  if (!port) {
    throw config::ConfigError(config.file, "transport", "the driver returned no port");
  }
  return port;
}

}  // namespace volcomp::daemon
