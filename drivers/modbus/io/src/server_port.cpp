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

template <typename Duration>
long long milliseconds(Duration d) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(d).count();
}

// Replies leave in one segment (Nagle would hold them for the master's delayed ACK); keepalive
// finds a peer that vanished without closing (power cut, reboot) while nothing is sent to it.
void tuneSocket(int fd, int keepaliveS) noexcept {
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  if (keepaliveS <= 0) return;
  int probes = 3;
  setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &one, sizeof one);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &keepaliveS, sizeof keepaliveS);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &keepaliveS, sizeof keepaliveS);
  setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &probes, sizeof probes);
}

}  // namespace

ModbusServerPort::ModbusServerPort(ModbusSettings settings, Notice notice)
    : settings_(std::move(settings)),
      notice_(std::move(notice)),
      layout_(layoutServerBank(settings_.registers)),
      rtuTracker_(settings_.registers) {
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
  // RTU: a frame stalled half-way is given up after this (TCP frames requests itself).
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
  const bool tcp = std::holds_alternative<TcpLink>(settings_.link);
  if (tcp) {
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
  rtuTracker_.reset();
  serving_ = true;
  notice(false, "modbus server listening on " + endpoint);
  thread_ = std::thread([this, tcp] { tcp ? serveTcp() : serveRtu(); });
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

void ModbusServerPort::closeClient(std::size_t index, const std::string& why) noexcept {
  const int fd = clients_[index].fd;
  const std::string peer = std::move(clients_[index].peer);
  clients_.erase(clients_.begin() + static_cast<std::ptrdiff_t>(index));
  ::close(fd);
  notice(false, "modbus master " + peer + " disconnected (" + why + ")");
}

void ModbusServerPort::acceptClient(SteadyClock::time_point now) noexcept {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  const int fd =
      ::accept4(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return;
  const std::string peer = peerName(addr);
  const auto& server = settings_.server;
  const char* refusal = nullptr;
  if (!clientAllowed(addr.sin_addr.s_addr, server.allowedClients)) {
    refusal = "address not in allowed_clients";
  } else if (static_cast<int>(clients_.size()) >= server.maxConnections) {
    // The slot of the connection silent longest, if it is silent long enough that it cannot be
    // a master polling: a PLC that rebooted, or an HMI that connected and went quiet.
    const auto quietest = std::min_element(
        clients_.begin(), clients_.end(),
        [](const Client& a, const Client& b) { return a.lastRequest < b.lastRequest; });
    const auto silence = now - quietest->lastRequest;
    if (silence >= std::chrono::milliseconds(server.takeoverAfterMs)) {
      ++counters_.replacedConnections;
      closeClient(
          static_cast<std::size_t>(quietest - clients_.begin()),
          "silent for " + std::to_string(milliseconds(silence)) + " ms, its slot taken by " + peer);
    } else {
      refusal = "max_connections reached";
    }
  }
  if (refusal != nullptr) {
    ++counters_.refusedConnections;
    ::close(fd);
    notice(true, "modbus server refused the connection from " + peer + ": " + refusal + " (" +
                     std::to_string(clients_.size()) + " of " +
                     std::to_string(server.maxConnections) + " open)");
    return;
  }
  tuneSocket(fd, server.keepaliveS);
  ++counters_.connections;
  clients_.emplace_back(fd, peer, settings_.registers, now);
  notice(false, "modbus master " + peer + " connected");
}

bool ModbusServerPort::receive(Client& client, SteadyClock::time_point now,
                               std::string& why) noexcept {
  // Full means a whole request is waiting (the largest fills the buffer exactly): read on once
  // it is answered.
  if (client.filled == client.received.size()) return true;
  const ssize_t n = ::recv(client.fd, client.received.data() + client.filled,
                           client.received.size() - client.filled, 0);
  if (n == 0) {
    why = "closed by the master";
    return false;
  }
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return true;
    why = std::string("broken: ") + std::strerror(errno);
    return false;
  }
  if (client.filled == 0) client.partialSince = now;
  client.filled += static_cast<std::size_t>(n);
  if (tcpAdu({client.received.data(), client.filled}).kind == TcpAduStatus::Kind::OutOfStep) {
    ++counters_.droppedConnections;
    why = "not a Modbus/TCP header (protocol id or length field)";
    return false;
  }
  return true;
}

int ModbusServerPort::reply(const std::uint8_t* adu, int length, std::span<const std::uint8_t> pdu,
                            PositionWriteTracker& tracker) noexcept {
  {
    std::lock_guard lock(mutex_);
    std::copy_n(outputs_.begin(), layout_.output.count,
                slice(mapping_->tab_registers, layout_.bank, layout_.output).begin());
  }
  const int sent = modbus_reply(ctx_, adu, length, mapping_);
  const auto request = parseServerRequest(pdu);
  if (!request || request->write.count == 0) return sent;
  bool complete = false;
  {
    std::lock_guard lock(mutex_);
    const auto in = slice(mapping_->tab_registers, layout_.bank, layout_.masterWrite);
    std::copy(in.begin(), in.end(), inputs_.begin());
    if (tracker.onWrite(request->write)) {
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
  return sent;
}

bool ModbusServerPort::answerTcp(Client& client, SteadyClock::time_point now) noexcept {
  const std::size_t bytes = tcpAdu({client.received.data(), client.filled}).bytes;
  const std::span<const std::uint8_t> adu(client.received.data(), bytes);
  const auto pdu = adu.subspan(kMbapBytes);
  ++counters_.requests;
  client.lastRequest = now;
  bool sent = false;
  if (const std::uint8_t code = refuseRequest(layout_, pdu); code != 0) {
    ++counters_.refused;
    const auto exception = tcpExceptionReply(adu, code);
    sent = ::send(client.fd, exception.data(), exception.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(exception.size());
  } else {
    modbus_set_socket(ctx_, client.fd);
    sent = reply(adu.data(), static_cast<int>(bytes), pdu, client.tracker) >= 0;
  }
  // A master may send its next request before this reply: keep what followed.
  client.filled -= bytes;
  std::memmove(client.received.data(), client.received.data() + bytes, client.filled);
  if (client.filled > 0) client.partialSince = now;
  return sent;
}

int ModbusServerPort::expireClients(SteadyClock::time_point now) noexcept {
  const auto requestTimeout = std::chrono::duration_cast<SteadyClock::duration>(
      std::chrono::duration<double, std::milli>(settings_.responseTimeoutMs));
  const std::chrono::seconds idleTimeout(settings_.server.idleTimeoutS);
  SteadyClock::time_point next = SteadyClock::time_point::max();
  for (std::size_t i = clients_.size(); i-- > 0;) {
    const Client& c = clients_[i];
    const bool partial = c.filled > 0 && tcpAdu({c.received.data(), c.filled}).kind ==
                                             TcpAduStatus::Kind::Incomplete;
    if (partial && now - c.partialSince >= requestTimeout) {
      ++counters_.droppedConnections;
      closeClient(i, "a request still incomplete after response_timeout_ms " +
                         std::to_string(milliseconds(now - c.partialSince)) + " ms");
      continue;
    }
    if (idleTimeout.count() > 0 && now - c.lastRequest >= idleTimeout) {
      ++counters_.droppedConnections;
      closeClient(i, "no request for idle_timeout_s " + std::to_string(idleTimeout.count()) + " s");
      continue;
    }
    if (partial) next = std::min(next, c.partialSince + requestTimeout);
    if (idleTimeout.count() > 0) next = std::min(next, c.lastRequest + idleTimeout);
  }
  if (next == SteadyClock::time_point::max()) return -1;
  // Rounded up, so that the wake-up finds the deadline passed.
  return static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(next - now).count() + 1);
}

void ModbusServerPort::serveTcp() noexcept {
  std::vector<pollfd> fds;
  fds.reserve(clients_.capacity() + 2);
  while (true) {
    const auto now = SteadyClock::now();
    int timeoutMs = expireClients(now);
    fds.clear();
    fds.push_back({wakeFd_, POLLIN, 0});
    fds.push_back({listenFd_, POLLIN, 0});
    for (const Client& c : clients_) {
      // A connection with a whole request waiting is not read further until it is answered.
      const bool waiting =
          tcpAdu({c.received.data(), c.filled}).kind == TcpAduStatus::Kind::Complete;
      if (waiting) timeoutMs = 0;
      fds.push_back({c.fd, static_cast<short>(waiting ? 0 : POLLIN), 0});
    }
    if (::poll(fds.data(), fds.size(), timeoutMs) < 0) {
      if (errno == EINTR) continue;
      failed_ = true;
      return;
    }
    if (fds[0].revents != 0) return;
    const auto polled = SteadyClock::now();
    // From the last, so that closing one does not shift those not yet seen.
    std::string why;
    for (std::size_t i = fds.size() - 1; i >= 2; --i) {
      if (fds[i].revents == 0) continue;
      if (!receive(clients_[i - 2], polled, why)) closeClient(i - 2, why);
    }
    // One request per connection per round: a master that sends many at once waits its turn.
    for (std::size_t i = clients_.size(); i-- > 0;) {
      Client& c = clients_[i];
      if (tcpAdu({c.received.data(), c.filled}).kind != TcpAduStatus::Kind::Complete) continue;
      if (!answerTcp(c, polled)) closeClient(i, "does not take its replies, or closed");
    }
    if ((fds[1].revents & POLLIN) != 0) acceptClient(polled);
  }
}

bool ModbusServerPort::answerRtu() noexcept {
  const int length = modbus_receive(ctx_, query_.data());
  if (length < 0) {
    // A frame with a bad CRC or cut short is dropped, as a real slave does; the device itself
    // stays usable.
    if (errno > MODBUS_ENOBASE || errno == ETIMEDOUT) {
      modbus_flush(ctx_);
      return true;
    }
    return false;
  }
  if (length == 0) return true;  // for another slave
  ++counters_.requests;
  const int header = modbus_get_header_length(ctx_);
  const int crc = 2;
  const std::span<const std::uint8_t> pdu(
      query_.data() + header, static_cast<std::size_t>(std::max(length - header - crc, 0)));
  if (const std::uint8_t code = refuseRequest(layout_, pdu); code != 0) {
    ++counters_.refused;
    if (query_[0] == 0) return true;  // a broadcast is never answered
    const std::uint8_t function = pdu.empty() ? 0 : pdu[0];
    const std::array<std::uint8_t, 3> exception = {
        query_[0], static_cast<std::uint8_t>(function | 0x80), code};
    modbus_send_raw_request(ctx_, exception.data(), static_cast<int>(exception.size()));
    return true;
  }
  reply(query_.data(), length, pdu, rtuTracker_);
  return true;
}

void ModbusServerPort::serveRtu() noexcept {
  const int fd = modbus_get_socket(ctx_);
  std::array<pollfd, 2> fds{};
  while (true) {
    fds[0] = {wakeFd_, POLLIN, 0};
    fds[1] = {fd, POLLIN, 0};
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      failed_ = true;
      return;
    }
    if (fds[0].revents != 0) return;
    if ((fds[1].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0 ||
        ((fds[1].revents & POLLIN) != 0 && !answerRtu())) {
      failed_ = true;
      notice(true, "modbus server: the serial device " + std::get<RtuLink>(settings_.link).device +
                       " failed (hang-up or error); reopening");
      return;
    }
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
