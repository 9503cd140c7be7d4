#pragma once
/// The simulated controller's Modbus server: holds the register map of an installation, answers
/// one client at a time on its own thread (TCP on 127.0.0.1, or RTU on a pseudo-terminal), fills
/// the input registers from the Machine before every reply and hands every write of the output
/// block to the Machine. Faults come from Machine::transportFault: stall (no reply), link down
/// (TCP: connection closed and the port not listening; RTU: silent), exception replies.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include "volcomp/config/modbus_config.hpp"
#include "volcomp/modbus/register_plan.hpp"
#include "volcomp/sim/machine.hpp"

struct _modbus;
struct _modbus_mapping_t;

namespace volcomp::sim {

class ModbusServer {
 public:
  /// `now` returns the machine time in seconds (monotonic).
  ModbusServer(modbus::RegisterMap map, int slaveId, Machine& machine, std::function<double()> now);
  ~ModbusServer();
  ModbusServer(const ModbusServer&) = delete;
  ModbusServer& operator=(const ModbusServer&) = delete;

  /// Listens on 127.0.0.1:port (0 = a free port) and starts serving. Throws std::system_error.
  void startTcp(std::uint16_t port);
  /// Opens a pseudo-terminal and serves RTU on its master side; clients open devicePath().
  /// Throws std::system_error.
  void startRtu();
  /// Stops the server thread and closes everything (idempotent).
  void stop() noexcept;

  std::uint16_t port() const noexcept { return port_; }
  const std::string& devicePath() const noexcept { return devicePath_; }
  /// The machine-readable line printed on stdout when serving:
  /// "LISTENING tcp 127.0.0.1 PORT" or "LISTENING rtu DEVICE".
  std::string listeningLine() const;

 private:
  void runTcp() noexcept;
  void runRtu() noexcept;
  /// Handles one received request of `length` bytes in req_.
  void handle(int length) noexcept;
  bool openListener() noexcept;
  void closeClient() noexcept;
  void closeListener() noexcept;

  const modbus::RegisterMap map_;
  const modbus::RegisterPlan plan_;
  const int slaveId_;
  Machine& machine_;
  const std::function<double()> now_;

  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;
  std::uint16_t port_ = 0;
  std::string devicePath_;
  int listenFd_ = -1;
  int clientFd_ = -1;
  int ptyMaster_ = -1;
  int ptySlave_ = -1;  // held open so that the master never sees a hang-up between clients
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  std::array<std::uint8_t, 260> req_{};  // MODBUS_MAX_ADU_LENGTH
};

}  // namespace volcomp::sim
