#pragma once
/// The Modbus controller connection (TCP or RTU) the compensation loop talks to, RAII over
/// libmodbus. One read() = one FC03 and/or one FC04 (one per register table holding inputs); one
/// write() = one FC16 of the whole output block. With `fc23` configured, write() is one FC23 that
/// writes the outputs and reads the holding-register inputs back in the same transaction, and the
/// next read() returns those inputs without a transaction (their age is then at most one cycle:
/// they were read when the previous cycle wrote). Buffers are preallocated: read() and write()
/// never allocate.
///
/// Errors: Modbus exception replies and protocol failures in volcomp::modbus::modbusCategory()
/// (the link is kept; the input buffer is flushed after a protocol failure); link loss as the
/// generic std::errc values volcomp::loop::isLinkError recognises (the connection is closed and
/// connect() must be called again). `link_loss_timeouts` consecutive response timeouts also count
/// as link loss (a stalled TCP peer, a pulled RS-485 cable): the port closes and reports
/// std::errc::not_connected.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <system_error>

#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/register_plan.hpp"
#include "volcomp/modbus/settings.hpp"

struct _modbus;  // libmodbus' modbus_t

namespace volcomp::modbus {

/// Counters for diagnostics (read by the owner thread only).
struct PortStatistics {
  std::uint64_t transactions = 0;
  std::uint64_t exceptions = 0;  ///< Modbus exception replies
  std::uint64_t timeouts = 0;
  std::uint64_t protocolErrors = 0;
  std::uint64_t linkLosses = 0;
};

class ModbusControllerPort final : public loop::ControllerPort {
 public:
  /// Creates the libmodbus context (no I/O yet). Throws std::system_error when libmodbus rejects
  /// the parameters.
  explicit ModbusControllerPort(ModbusSettings settings);
  ~ModbusControllerPort() override;
  ModbusControllerPort(const ModbusControllerPort&) = delete;
  ModbusControllerPort& operator=(const ModbusControllerPort&) = delete;

  std::error_code connect() noexcept override;
  void disconnect() noexcept override;
  bool connected() const noexcept override { return connected_; }
  std::error_code read(loop::AxisSample& out) noexcept override;
  std::error_code write(const loop::OffsetCommand& command) noexcept override;

  const ModbusSettings& settings() const noexcept { return settings_; }
  const RegisterPlan& plan() const noexcept { return plan_; }
  const PortStatistics& statistics() const noexcept { return stats_; }
  /// The registers of the last read (holding and input blocks at their plan addresses) and of
  /// the last write, raw, for commissioning (describeInputs / describeOutputs).
  ConstTableView lastHoldingRead() const noexcept {
    return {std::span<const std::uint16_t>(holding_.data(), holding_.size()),
            plan_.holdingRead.start};
  }
  ConstTableView lastInputRead() const noexcept {
    return {std::span<const std::uint16_t>(input_.data(), input_.size()), plan_.inputRead.start};
  }
  ConstTableView lastWrite() const noexcept {
    return {std::span<const std::uint16_t>(output_.data(), output_.size()), plan_.write.start};
  }

 private:
  struct ContextDeleter {
    void operator()(_modbus* ctx) const noexcept;
  };
  /// Classifies a failed libmodbus call (errno `err`): closes the link on link loss.
  std::error_code fail(int err) noexcept;
  void succeeded() noexcept { consecutiveTimeouts_ = 0; }
  std::error_code readTables() noexcept;

  ModbusSettings settings_;
  RegisterPlan plan_;
  std::unique_ptr<_modbus, ContextDeleter> ctx_;
  bool connected_ = false;
  int consecutiveTimeouts_ = 0;
  bool prefetched_ = false;  ///< holding_ holds inputs read by the last FC23
  std::array<std::uint16_t, 125> holding_{};
  std::array<std::uint16_t, 125> input_{};
  std::array<std::uint16_t, 123> output_{};
  PortStatistics stats_;
};

}  // namespace volcomp::modbus
