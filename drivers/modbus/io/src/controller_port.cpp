#include "volcomp/modbus/controller_port.hpp"

#include <cerrno>
#include <cmath>
#include <utility>

#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include "libmodbus_errno.hpp"
#include "volcomp/modbus/error.hpp"

namespace volcomp::modbus {
namespace {

bool isExceptionOrProtocol(int err) noexcept {
  return err > MODBUS_ENOBASE;
}

/// errno values after which the connection cannot carry another transaction.
std::error_code linkLossCode(int err) noexcept {
  switch (err) {
    case ECONNRESET:
      return std::make_error_code(std::errc::connection_reset);
    case EPIPE:
      return std::make_error_code(std::errc::broken_pipe);
    case ENETDOWN:
      return std::make_error_code(std::errc::network_down);
    case ENETUNREACH:
      return std::make_error_code(std::errc::network_unreachable);
    case EHOSTUNREACH:
      return std::make_error_code(std::errc::host_unreachable);
    case ECONNABORTED:
      return std::make_error_code(std::errc::connection_aborted);
    case ECONNREFUSED:
      return std::make_error_code(std::errc::connection_refused);
    // EBADF, EIO (serial adapter unplugged), ENXIO, ENOTCONN and anything unexpected from the
    // socket or tty layer: the descriptor is unusable.
    default:
      return std::make_error_code(std::errc::not_connected);
  }
}

void toTimeval(double ms, std::uint32_t& sec, std::uint32_t& usec) noexcept {
  const auto total = static_cast<std::uint64_t>(std::llround(ms * 1000.0));
  sec = static_cast<std::uint32_t>(total / 1000000U);
  usec = static_cast<std::uint32_t>(total % 1000000U);
}

}  // namespace

void ModbusControllerPort::ContextDeleter::operator()(_modbus* ctx) const noexcept {
  modbus_close(ctx);
  modbus_free(ctx);
}

ModbusControllerPort::ModbusControllerPort(ModbusSettings settings)
    : settings_(std::move(settings)), plan_(planRegisters(settings_.registers)) {
  modbus_t* raw = nullptr;
  if (const auto* tcp = std::get_if<TcpLink>(&settings_.link)) {
    raw = modbus_new_tcp_pi(tcp->host.c_str(), std::to_string(tcp->port).c_str());
  } else {
    const auto& rtu = std::get<RtuLink>(settings_.link);
    raw = modbus_new_rtu(rtu.device.c_str(), rtu.baud, rtu.parity, rtu.dataBits, rtu.stopBits);
  }
  if (raw == nullptr) {
    throw std::system_error(errno, std::generic_category(), "cannot create the Modbus context");
  }
  ctx_.reset(raw);
  // The daemon owns reconnection with its own backoff; libmodbus' recovery would retry a failed
  // send forever inside one call.
  modbus_set_error_recovery(raw, MODBUS_ERROR_RECOVERY_NONE);
  if (modbus_set_slave(raw, settings_.slaveId) != 0) {
    throw std::system_error(errno, std::generic_category(), "invalid Modbus slave id");
  }
  std::uint32_t sec = 0, usec = 0;
  toTimeval(settings_.responseTimeoutMs, sec, usec);
  modbus_set_response_timeout(raw, sec, usec);
  // A response stalled half-way must not hold the cycle longer than a missing one.
  modbus_set_byte_timeout(raw, sec, usec);
}

ModbusControllerPort::~ModbusControllerPort() = default;

std::error_code ModbusControllerPort::connect() noexcept {
  if (connected_) return {};
  prefetched_ = false;
  consecutiveTimeouts_ = 0;
  if (modbus_connect(ctx_.get()) != 0) {
    const int err = errno;
    modbus_close(ctx_.get());
    return linkLossCode(err);
  }
  if (std::holds_alternative<TcpLink>(settings_.link)) {
    // A request must leave in one segment: with Nagle and the peer's delayed ACK a split request
    // costs ~40 ms.
    int one = 1;
    setsockopt(modbus_get_socket(ctx_.get()), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }
  connected_ = true;
  return {};
}

void ModbusControllerPort::disconnect() noexcept {
  if (!connected_) return;
  modbus_close(ctx_.get());
  connected_ = false;
  prefetched_ = false;
}

std::error_code ModbusControllerPort::fail(int err) noexcept {
  prefetched_ = false;
  if (isExceptionOrProtocol(err)) {
    if (err > MODBUS_ENOBASE && err <= EMBXGTAR) {
      ++stats_.exceptions;
    } else {
      ++stats_.protocolErrors;
      // A malformed or mismatched response may leave bytes of it in the input queue; the next
      // transaction must start on a clean frame.
      modbus_flush(ctx_.get());
    }
    consecutiveTimeouts_ = 0;
    return fromLibmodbusErrno(err);
  }
  if (err == ETIMEDOUT) {
    ++stats_.timeouts;
    // A late response would otherwise be taken for the answer to the next request.
    modbus_flush(ctx_.get());
    if (++consecutiveTimeouts_ >= settings_.linkLossTimeouts) {
      ++stats_.linkLosses;
      disconnect();
      return std::make_error_code(std::errc::not_connected);
    }
    return Errc::response_timeout;
  }
  ++stats_.linkLosses;
  disconnect();
  return linkLossCode(err);
}

std::error_code ModbusControllerPort::readTables() noexcept {
  modbus_t* ctx = ctx_.get();
  if (plan_.holdingRead.count > 0) {
    ++stats_.transactions;
    if (modbus_read_registers(ctx, plan_.holdingRead.start, plan_.holdingRead.count,
                              holding_.data()) != plan_.holdingRead.count) {
      return fail(errno);
    }
  }
  if (plan_.inputRead.count > 0) {
    ++stats_.transactions;
    if (modbus_read_input_registers(ctx, plan_.inputRead.start, plan_.inputRead.count,
                                    input_.data()) != plan_.inputRead.count) {
      return fail(errno);
    }
  }
  succeeded();
  return {};
}

std::error_code ModbusControllerPort::read(loop::AxisSample& out) noexcept {
  if (!connected_) return std::make_error_code(std::errc::not_connected);
  if (prefetched_) {
    prefetched_ = false;
  } else if (auto ec = readTables()) {
    return ec;
  }
  return decodeInputs(
      settings_.registers,
      ConstTableView{std::span<const std::uint16_t>(holding_.data(), holding_.size()),
                     plan_.holdingRead.start},
      ConstTableView{std::span<const std::uint16_t>(input_.data(), input_.size()),
                     plan_.inputRead.start},
      out);
}

std::error_code ModbusControllerPort::write(const loop::OffsetCommand& command) noexcept {
  if (!connected_) return std::make_error_code(std::errc::not_connected);
  prefetched_ = false;
  if (auto ec = encodeOutputs(
          settings_.registers, command,
          TableView{std::span<std::uint16_t>(output_.data(), output_.size()), plan_.write.start})) {
    return ec;
  }
  modbus_t* ctx = ctx_.get();
  ++stats_.transactions;
  if (settings_.registers.fc23 && plan_.holdingRead.count > 0) {
    if (modbus_write_and_read_registers(ctx, plan_.write.start, plan_.write.count, output_.data(),
                                        plan_.holdingRead.start, plan_.holdingRead.count,
                                        holding_.data()) != plan_.holdingRead.count) {
      return fail(errno);
    }
    prefetched_ = true;
  } else if (modbus_write_registers(ctx, plan_.write.start, plan_.write.count, output_.data()) !=
             plan_.write.count) {
    return fail(errno);
  }
  succeeded();
  return {};
}

}  // namespace volcomp::modbus
