#include "volcomp/modbus/server_port.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>

#include <arpa/inet.h>
#include <fcntl.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include "volcomp/modbus/error.hpp"

namespace volcomp::modbus {
namespace {

std::string peerName(const sockaddr_in& addr) {
  char text[INET_ADDRSTRLEN] = {};
  inet_ntop(AF_INET, &addr.sin_addr, text, sizeof text);
  return std::string(text) + ":" + std::to_string(ntohs(addr.sin_port));
}

std::span<std::uint16_t> slice(std::uint16_t* table, Block bank, Block part) noexcept {
  return {table + (part.start - bank.start), part.count};
}

}  // namespace

ModbusServerPort::ModbusServerPort(ModbusSettings settings, Notice notice)
    : settings_(std::move(settings)),
      notice_(std::move(notice)),
      layout_(layoutServerBank(settings_.registers)),
      tracker_(settings_.registers) {
  if (const auto* tcp = std::get_if<TcpLink>(&settings_.link)) {
    ctx_ = modbus_new_tcp(settings_.server.listenAddress.c_str(), tcp->port);
  } else {
    const auto& rtu = std::get<RtuLink>(settings_.link);
    ctx_ = modbus_new_rtu(rtu.device.c_str(), rtu.baud, rtu.parity, rtu.dataBits, rtu.stopBits);
  }
  if (ctx_ == nullptr) {
    throw std::system_error(errno, std::generic_category(), "cannot create the Modbus context");
  }
  modbus_set_error_recovery(ctx_, MODBUS_ERROR_RECOVERY_NONE);
  if (modbus_set_slave(ctx_, settings_.slaveId) != 0) {
    modbus_free(ctx_);
    throw std::system_error(errno, std::generic_category(), "invalid Modbus slave id");
  }
  // A request stalled half-way must not hold the other connections longer than this.
  const auto usec = static_cast<std::uint32_t>(std::llround(settings_.responseTimeoutMs * 1000.0));
  modbus_set_byte_timeout(ctx_, usec / 1000000U, usec % 1000000U);
  mapping_ =
      modbus_mapping_new_start_address(0, 0, 0, 0, layout_.bank.start, layout_.bank.count, 0, 0);
  if (mapping_ == nullptr) {
    modbus_free(ctx_);
    throw std::system_error(errno, std::generic_category(), "cannot allocate the register bank");
  }
  clients_.reserve(static_cast<std::size_t>(std::max(settings_.server.maxConnections, 1)));
}

ModbusServerPort::~ModbusServerPort() {
  disconnect();
  modbus_mapping_free(mapping_);
  modbus_free(ctx_);
}

void ModbusServerPort::notice(bool warning, const std::string& line) const {
  if (notice_) notice_(warning, line);
}

std::error_code ModbusServerPort::connect() noexcept {
  if (connected()) return {};
  disconnect();  // an RTU device that failed: close it before opening it again
  failed_ = false;
  wakeFd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (wakeFd_ < 0) return {errno, std::generic_category()};
  std::string endpoint;
  if (const auto* tcp = std::get_if<TcpLink>(&settings_.link)) {
    listenFd_ = modbus_tcp_listen(ctx_, std::max(settings_.server.maxConnections, 1));
    if (listenFd_ < 0) {
      const int err = errno;
      ::close(wakeFd_);
      wakeFd_ = -1;
      return {err, std::generic_category()};
    }
    sockaddr_in addr{};
    socklen_t len = sizeof addr;
    getsockname(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len);
    boundPort_ = ntohs(addr.sin_port);
    endpoint = "tcp " + settings_.server.listenAddress + ":" + std::to_string(boundPort_);
    (void)tcp;
  } else {
    if (modbus_connect(ctx_) != 0) {
      const int err = errno;
      ::close(wakeFd_);
      wakeFd_ = -1;
      return {err, std::generic_category()};
    }
    endpoint = "rtu " + std::get<RtuLink>(settings_.link).device + " as slave " +
               std::to_string(settings_.slaveId);
  }
  {
    std::lock_guard lock(mutex_);
    haveSet_ = false;
    inputs_.fill(0);
  }
  std::fill(mapping_->tab_registers, mapping_->tab_registers + mapping_->nb_registers, 0);
  tracker_.reset();
  serving_ = true;
  notice(false, "modbus server listening on " + endpoint);
  thread_ = std::thread([this] { serve(); });
  return {};
}

void ModbusServerPort::disconnect() noexcept {
  if (thread_.joinable()) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(wakeFd_, &one, sizeof one);
    thread_.join();
  }
  while (!clients_.empty()) closeClient(clients_.size() - 1, "server stopped");
  if (listenFd_ >= 0) ::close(listenFd_);
  listenFd_ = -1;
  if (wakeFd_ >= 0) ::close(wakeFd_);
  wakeFd_ = -1;
  if (serving_ && std::holds_alternative<RtuLink>(settings_.link)) modbus_close(ctx_);
  modbus_set_socket(ctx_, -1);
  serving_ = false;
}

void ModbusServerPort::closeClient(std::size_t index, const char* why) noexcept {
  const Client client = std::move(clients_[index]);
  clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(index));
  ::close(client.fd);
  // A set half-written by a master that is gone must not be completed by another.
  tracker_.reset();
  notice(false, "modbus master " + client.peer + " disconnected (" + why + ")");
}

void ModbusServerPort::acceptClient() noexcept {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  const int fd =
      ::accept4(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return;
  const std::string peer = peerName(addr);
  const char* refusal = nullptr;
  if (!clientAllowed(addr.sin_addr.s_addr, settings_.server.allowedClients)) {
    refusal = "address not in allowed_clients";
  } else if (static_cast<int>(clients_.size()) >= settings_.server.maxConnections) {
    refusal = "max_connections reached";
  }
  if (refusal != nullptr) {
    ++counters_.refusedConnections;
    ::close(fd);
    notice(true, "modbus server refused the connection from " + peer + ": " + refusal + " (" +
                     std::to_string(clients_.size()) + " of " +
                     std::to_string(settings_.server.maxConnections) + " open)");
    return;
  }
  // Replies leave in one segment (Nagle would hold them for the master's delayed ACK); the
  // socket is non-blocking so that a master that does not read its replies is dropped instead
  // of blocking the others.
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  ++counters_.connections;
  clients_.push_back({fd, peer});
  notice(false, "modbus master " + peer + " connected");
}

bool ModbusServerPort::answer(int fd) noexcept {
  modbus_set_socket(ctx_, fd);
  const int length = modbus_receive(ctx_, query_.data());
  if (length < 0) {
    const int err = errno;
    // RTU: a frame with a bad CRC or cut short is dropped, as a real slave does; the device
    // itself stays usable. TCP: the stream is out of step or closed.
    if (std::holds_alternative<RtuLink>(settings_.link) &&
        (err > MODBUS_ENOBASE || err == ETIMEDOUT)) {
      modbus_flush(ctx_);
      return true;
    }
    return false;
  }
  if (length == 0) return true;  // for another slave (RTU)
  ++counters_.requests;
  const int header = modbus_get_header_length(ctx_);
  const auto request = parseServerRequest(std::span<const std::uint8_t>(
      query_.data() + header, static_cast<std::size_t>(std::max(length - header, 0))));
  if (request) {
    if (const std::uint8_t code = refuseRequest(layout_, *request); code != 0) {
      ++counters_.refused;
      return modbus_reply_exception(ctx_, query_.data(), code) >= 0 ||
             std::holds_alternative<RtuLink>(settings_.link);
    }
  }
  {
    std::lock_guard lock(mutex_);
    std::copy_n(outputs_.begin(), layout_.output.count,
                slice(mapping_->tab_registers, layout_.bank, layout_.output).begin());
  }
  const int sent = modbus_reply(ctx_, query_.data(), length, mapping_);
  if (request && request->write.count > 0) {
    bool complete = false;
    {
      std::lock_guard lock(mutex_);
      const auto in = slice(mapping_->tab_registers, layout_.bank, layout_.masterWrite);
      std::copy(in.begin(), in.end(), inputs_.begin());
      if (tracker_.onWrite(request->write)) {
        complete = true;
        ++counters_.positionSets;
        const auto& life = settings_.registers.sequence;
        const std::uint16_t value =
            life ? mapping_->tab_registers[life->address - layout_.bank.start] : lastLife_;
        if (!life || !haveSet_ || value != lastLife_) {
          ++freshness_;
          lastLife_ = value;
        }
        haveSet_ = true;
      }
    }
    if (complete && trigger_ && settings_.server.trigger == CycleTrigger::Write &&
        !triggerPending_.exchange(true)) {
      trigger_();
    }
  }
  return sent >= 0 || std::holds_alternative<RtuLink>(settings_.link);
}

void ModbusServerPort::serve() noexcept {
  const bool tcp = std::holds_alternative<TcpLink>(settings_.link);
  const int rtuFd = tcp ? -1 : modbus_get_socket(ctx_);
  std::vector<pollfd> fds;
  fds.reserve(clients_.capacity() + 2);
  while (true) {
    fds.clear();
    fds.push_back({wakeFd_, POLLIN, 0});
    fds.push_back({tcp ? listenFd_ : rtuFd, POLLIN, 0});
    for (const Client& c : clients_) fds.push_back({c.fd, POLLIN, 0});
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      failed_ = true;
      return;
    }
    if (fds[0].revents != 0) return;
    if (!tcp) {
      if ((fds[1].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0 ||
          ((fds[1].revents & POLLIN) != 0 && !answer(rtuFd))) {
        failed_ = true;
        notice(true, "modbus server: the serial device " +
                         std::get<RtuLink>(settings_.link).device +
                         " failed (hang-up or error); reopening");
        return;
      }
      continue;
    }
    // Connections first, from the last, so that closing one does not shift those not yet seen.
    for (std::size_t i = fds.size() - 1; i >= 2; --i) {
      if (fds[i].revents == 0) continue;
      const std::size_t index = i - 2;
      if (!answer(clients_[index].fd)) closeClient(index, "closed by the master or broken");
    }
    if ((fds[1].revents & POLLIN) != 0) acceptClient();
  }
}

std::error_code ModbusServerPort::read(loop::AxisSample& out) noexcept {
  if (!connected()) return std::make_error_code(std::errc::not_connected);
  std::uint16_t freshness = 0;
  {
    std::lock_guard lock(mutex_);
    triggerPending_ = false;
    if (!haveSet_) return Errc::no_master_write;
    std::copy_n(inputs_.begin(), layout_.masterWrite.count, readBuffer_.begin());
    freshness = freshness_;
  }
  const std::error_code ec = decodeInputs(
      settings_.registers,
      ConstTableView{std::span<const std::uint16_t>(readBuffer_.data(), readBuffer_.size()),
                     layout_.masterWrite.start},
      ConstTableView{}, out);
  out.hasSequence = true;
  out.sequence = freshness;
  return ec;
}

std::error_code ModbusServerPort::write(const loop::OffsetCommand& command) noexcept {
  if (!connected()) return std::make_error_code(std::errc::not_connected);
  if (auto ec = encodeOutputs(
          settings_.registers, command,
          TableView{std::span<std::uint16_t>(writeBuffer_.data(), writeBuffer_.size()),
                    layout_.output.start})) {
    return ec;
  }
  std::lock_guard lock(mutex_);
  std::copy_n(writeBuffer_.begin(), layout_.output.count, outputs_.begin());
  return {};
}

}  // namespace volcomp::modbus
