#include "transports.hpp"

#include <system_error>
#include <type_traits>
#include <variant>

#include <spdlog/spdlog.h>
#include "volcomp/can/controller_port.hpp"

#include "program.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/modbus/controller_port.hpp"
#include "volcomp/modbus/server_port.hpp"

namespace volcomp::volcompd {

std::unique_ptr<loop::ControllerPort> makeControllerPort(const config::TransportSettings& settings,
                                                         const std::string& file) {
  return std::visit(
      [&](const auto& driverSettings) -> std::unique_ptr<loop::ControllerPort> {
        using Settings = std::decay_t<decltype(driverSettings)>;
        if constexpr (std::is_same_v<Settings, modbus::ModbusSettings>) {
          try {
            if (driverSettings.role == modbus::ModbusRole::Server) {
              return std::make_unique<modbus::ModbusServerPort>(
                  driverSettings, [](bool warning, std::string_view line) {
                    spdlog::log(warning ? spdlog::level::warn : spdlog::level::info, "{}", line);
                  });
            }
            return std::make_unique<modbus::ModbusControllerPort>(driverSettings);
          } catch (const std::system_error& e) {
            // Validated settings make this unreachable in practice; if libmodbus still refuses
            // them, the daemon reports it like any other configuration error.
            throw config::ConfigError(file, "transport",
                                      std::string("libmodbus refused the settings: ") + e.what());
          }
        } else if constexpr (std::is_same_v<Settings, linuxcnc::HalSettings>) {
          // volcompd-linuxcnc only (program.hpp).
          return makeLinuxCncPort(driverSettings, file);
        } else {
          return std::make_unique<can::CanControllerPort>(driverSettings);
        }
      },
      settings);
}

void connectCycleTrigger(loop::ControllerPort& port, std::function<void()> runCycle) {
  if (auto* server = dynamic_cast<modbus::ModbusServerPort*>(&port)) {
    if (server->settings().server.trigger == modbus::CycleTrigger::Write) {
      server->setCycleTrigger(std::move(runCycle));
    }
  }
}

}  // namespace volcomp::volcompd
