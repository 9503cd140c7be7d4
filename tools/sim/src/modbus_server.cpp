#include "volcomp/sim/modbus_server.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <system_error>

#include <arpa/inet.h>
#include <fcntl.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

namespace volcomp::sim {
namespace {

// Poll period of the server loop: how quickly it notices stop() and link-drop commands.
constexpr int kPollMs = 10;

[[noreturn]] void throwErrno(const char* what) {
  throw std::system_error(errno, std::generic_category(), what);
}

std::uint16_t word(const std::uint8_t* p) noexcept {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

// Holds the reply for `seconds` (fault injection), in slices so that stop() is not delayed.
void holdReply(double seconds, const std::atomic<bool>& stopping) noexcept {
  const auto until =
      std::chrono::steady_clock::now() +
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(seconds));
  while (!stopping) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        until - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd none{};
    ::poll(&none, 0, static_cast<int>(std::min<std::int64_t>(left.count(), kPollMs)));
  }
}

}  // namespace

ModbusServer::ModbusServer(modbus::RegisterMap map, int slaveId, Machine& machine,
                           std::function<double()> now)
    : map_(std::move(map)),
      plan_(modbus::planRegisters(map_)),
      slaveId_(slaveId),
      machine_(machine),
      now_(std::move(now)) {
  // The holding table covers the holding inputs and the outputs; anything else gets an
  // "illegal data address" exception, as from a real controller.
  int hLo = plan_.write.start, hHi = plan_.write.start + plan_.write.count;
  if (plan_.holdingRead.count > 0) {
    hLo = std::min<int>(hLo, plan_.holdingRead.start);
    hHi = std::max<int>(hHi, plan_.holdingRead.start + plan_.holdingRead.count);
  }
  mapping_ = modbus_mapping_new_start_address(0, 0, 0, 0, static_cast<unsigned>(hLo),
                                              static_cast<unsigned>(hHi - hLo),
                                              plan_.inputRead.start, plan_.inputRead.count);
  if (mapping_ == nullptr) throwErrno("cannot allocate the register mapping");
}

ModbusServer::~ModbusServer() {
  stop();
  modbus_mapping_free(mapping_);
}

std::string ModbusServer::listeningLine() const {
  if (!devicePath_.empty()) return "LISTENING rtu " + devicePath_;
  return "LISTENING tcp 127.0.0.1 " + std::to_string(port_);
}

bool ModbusServer::openListener() noexcept {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  int one = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port_);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 1) != 0) {
    ::close(fd);
    return false;
  }
  socklen_t len = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
  listenFd_ = fd;
  return true;
}

void ModbusServer::startTcp(std::uint16_t port) {
  port_ = port;
  if (!openListener()) throwErrno("cannot listen on 127.0.0.1");
  ctx_ = modbus_new_tcp("127.0.0.1", port_);
  if (ctx_ == nullptr) throwErrno("cannot create the Modbus TCP context");
  thread_ = std::thread([this] { runTcp(); });
}

void ModbusServer::startRtu() {
  char name[256] = {};
  if (openpty(&ptyMaster_, &ptySlave_, name, nullptr, nullptr) != 0) throwErrno("openpty");
  termios tio{};
  tcgetattr(ptySlave_, &tio);
  cfmakeraw(&tio);
  tcsetattr(ptySlave_, TCSANOW, &tio);
  devicePath_ = name;
  ctx_ = modbus_new_rtu(devicePath_.c_str(), 115200, 'N', 8, 1);
  if (ctx_ == nullptr) throwErrno("cannot create the Modbus RTU context");
  modbus_set_slave(ctx_, slaveId_);
  // The master side is not a device one can open: hand libmodbus the descriptor directly.
  modbus_set_socket(ctx_, ptyMaster_);
  thread_ = std::thread([this] { runRtu(); });
}

void ModbusServer::stop() noexcept {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
  closeClient();
  closeListener();
  if (ctx_ != nullptr) {
    // Not modbus_close: the descriptors are ours (and RTU would restore termios it never saved).
    modbus_set_socket(ctx_, -1);
    modbus_free(ctx_);
    ctx_ = nullptr;
  }
  if (ptyMaster_ >= 0) ::close(ptyMaster_);
  if (ptySlave_ >= 0) ::close(ptySlave_);
  ptyMaster_ = ptySlave_ = -1;
}

void ModbusServer::closeClient() noexcept {
  if (clientFd_ >= 0) ::close(clientFd_);
  clientFd_ = -1;
}

void ModbusServer::closeListener() noexcept {
  if (listenFd_ >= 0) ::close(listenFd_);
  listenFd_ = -1;
}

void ModbusServer::runTcp() noexcept {
  while (!stopping_) {
    if (machine_.transportFault(now_()).linkDown) {
      // Listener first: a client that sees its connection reset must find the port refusing,
      // not a backlog that is about to be discarded.
      closeListener();
      closeClient();
      pollfd none{};
      ::poll(&none, 0, kPollMs);
      continue;
    }
    if (listenFd_ < 0 && !openListener()) {
      pollfd none{};
      ::poll(&none, 0, kPollMs);
      continue;
    }
    pollfd p{clientFd_ >= 0 ? clientFd_ : listenFd_, POLLIN, 0};
    if (::poll(&p, 1, kPollMs) <= 0) continue;
    if (clientFd_ < 0) {
      const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (fd < 0) continue;
      // libmodbus sets TCP_NODELAY only on client sockets; a reply split by Nagle would wait
      // for the peer's delayed ACK.
      int one = 1;
      setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      clientFd_ = fd;
      modbus_set_socket(ctx_, fd);
      machine_.onSessionStart(now_());
      continue;
    }
    const int rc = modbus_receive(ctx_, req_.data());
    if (rc < 0) {
      // Peer closed or broken stream: wait for the next client.
      closeClient();
      modbus_set_socket(ctx_, -1);
      continue;
    }
    if (rc > 0) handle(rc);
  }
}

void ModbusServer::runRtu() noexcept {
  machine_.onSessionStart(now_());
  while (!stopping_) {
    pollfd p{ptyMaster_, POLLIN, 0};
    if (::poll(&p, 1, kPollMs) <= 0) continue;
    const int rc = modbus_receive(ctx_, req_.data());
    if (rc < 0) {
      // Bad CRC or a partial frame: drop what is left of it, as a real RTU slave would.
      modbus_flush(ctx_);
      continue;
    }
    if (rc > 0) handle(rc);
  }
}

void ModbusServer::handle(int length) noexcept {
  const double t = now_();
  const TransportFault fault = machine_.transportFault(t);
  if (fault.stall || fault.linkDown) {
    machine_.countRequest(false, false);
    return;
  }
  if (fault.exceptionCode != 0) {
    modbus_reply_exception(ctx_, req_.data(), static_cast<unsigned>(fault.exceptionCode));
    machine_.countRequest(true, true);
    return;
  }
  const int h = modbus_get_header_length(ctx_);
  const std::uint8_t* pdu = req_.data() + h;
  const int fc = pdu[0];
  // Write part of the request, if any: start address, count, big-endian values.
  int wAddr = -1, wCount = 0;
  const std::uint8_t* wValues = nullptr;
  if (fc == MODBUS_FC_WRITE_SINGLE_REGISTER && length >= h + 5) {
    wAddr = word(pdu + 1);
    wCount = 1;
    wValues = pdu + 3;
  } else if (fc == MODBUS_FC_WRITE_MULTIPLE_REGISTERS && length >= h + 6) {
    wAddr = word(pdu + 1);
    wCount = word(pdu + 3);
    wValues = pdu + 6;
    if (length < h + 6 + 2 * wCount) wAddr = -1;
  } else if (fc == MODBUS_FC_WRITE_AND_READ_REGISTERS && length >= h + 10) {
    wAddr = word(pdu + 5);
    wCount = word(pdu + 7);
    wValues = pdu + 10;
    if (length < h + 10 + 2 * wCount) wAddr = -1;
  }
  const int hStart = mapping_->start_registers;
  const int hCount = mapping_->nb_registers;
  bool wroteOutputs = false;
  if (wAddr >= 0 && wAddr >= hStart && wAddr + wCount <= hStart + hCount) {
    // Apply the write before filling the inputs, so that an FC23 read-back and `actual`
    // positions already reflect it (the server executes the write before the read).
    for (int i = 0; i < wCount; ++i) {
      mapping_->tab_registers[wAddr - hStart + i] = word(wValues + 2 * i);
    }
    const int outLo = plan_.write.start, outHi = plan_.write.start + plan_.write.count;
    if (wAddr < outHi && outLo < wAddr + wCount) {
      loop::OffsetCommand command;
      modbus::decodeOutputs(
          map_,
          modbus::ConstTableView{std::span<const std::uint16_t>(mapping_->tab_registers,
                                                                static_cast<std::size_t>(hCount)),
                                 static_cast<std::uint16_t>(hStart)},
          command);
      machine_.onWrite(t, command, !(wAddr <= outLo && wAddr + wCount >= outHi));
      wroteOutputs = true;
    }
  }
  const loop::AxisSample inputs = machine_.inputs(t);
  modbus::encodeInputs(
      map_, inputs,
      modbus::TableView{
          std::span<std::uint16_t>(mapping_->tab_registers, static_cast<std::size_t>(hCount)),
          static_cast<std::uint16_t>(hStart)},
      modbus::TableView{
          std::span<std::uint16_t>(mapping_->tab_input_registers,
                                   static_cast<std::size_t>(mapping_->nb_input_registers)),
          static_cast<std::uint16_t>(mapping_->start_input_registers)});
  // Faults of the reply: a write applied but answered late or never; a client stopped between
  // the read it is waiting for and the write that follows (SIGSTOP before the answer, so that it
  // cannot write before it is stopped; SIGCONT once the answer waits in its socket).
  if (wroteOutputs) {
    const WriteReply fate = machine_.takeWriteReply();
    if (fate.drop) {
      machine_.countRequest(false, false);
      return;
    }
    if (fate.delayS > 0.0) holdReply(fate.delayS, stopping_);
  }
  ClientPause pause;
  if (wAddr < 0) pause = machine_.takeClientPause();
  if (pause.pid > 0 && ::kill(pause.pid, SIGSTOP) == 0) {
    holdReply(pause.seconds, stopping_);
    modbus_reply(ctx_, req_.data(), length, mapping_);
    ::kill(pause.pid, SIGCONT);
  } else {
    modbus_reply(ctx_, req_.data(), length, mapping_);
  }
  machine_.countRequest(true, false);
}

}  // namespace volcomp::sim
