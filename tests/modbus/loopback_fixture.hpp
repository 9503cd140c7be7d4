#pragma once
// An in-process simulated controller (Machine + ModbusServer on a free port or a pty) and the
// driver connected to it.

#include <chrono>
#include <memory>
#include <optional>

#include <gtest/gtest.h>

#include "test_maps.hpp"
#include "volcomp/config/modbus_config.hpp"
#include "volcomp/modbus/controller_port.hpp"
#include "volcomp/sim/machine.hpp"
#include "volcomp/sim/modbus_server.hpp"

namespace volcomp::test {

inline sim::Vec3 noError(const sim::Vec3&, const sim::MotionDirections&) {
  return {};
}

class SimClock {
 public:
  double operator()() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

struct Loopback {
  SimClock clock;
  sim::Machine machine;
  std::unique_ptr<sim::ModbusServer> server;
  std::unique_ptr<modbus::ModbusControllerPort> port;

  /// A machine standing at `positionMm` (a one-point path) with no true error.
  Loopback(const sim::Vec3& positionMm, const sim::MachineOptions& options)
      : machine(sim::Path::polyline({positionMm}, 1000.0), noError, options) {}

  static std::unique_ptr<Loopback> tcp(const sim::Vec3& at, const sim::MachineOptions& options = {},
                                       bool fc23 = false) {
    auto lb = std::make_unique<Loopback>(at, options);
    const auto cfg = config::parseModbusSettings(tcpTransportJson(1, fc23), "test", "transport");
    lb->server = std::make_unique<sim::ModbusServer>(cfg.registers, cfg.slaveId, lb->machine,
                                                     [c = lb->clock] { return c(); });
    lb->server->startTcp(0);
    lb->port = std::make_unique<modbus::ModbusControllerPort>(config::parseModbusSettings(
        tcpTransportJson(lb->server->port(), fc23), "test", "transport"));
    return lb;
  }

  static std::unique_ptr<Loopback> rtu(const sim::Vec3& at,
                                       const sim::MachineOptions& options = {}) {
    auto lb = std::make_unique<Loopback>(at, options);
    const auto cfg =
        config::parseModbusSettings(rtuTransportJson("/dev/null"), "test", "transport");
    lb->server = std::make_unique<sim::ModbusServer>(cfg.registers, cfg.slaveId, lb->machine,
                                                     [c = lb->clock] { return c(); });
    lb->server->startRtu();
    lb->port = std::make_unique<modbus::ModbusControllerPort>(config::parseModbusSettings(
        rtuTransportJson(lb->server->devicePath()), "test", "transport"));
    return lb;
  }

  double now() const { return clock(); }
};

}  // namespace volcomp::test
