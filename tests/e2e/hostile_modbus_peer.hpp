#pragma once
// A hostile Modbus TCP server for whole-process tests: a man in the middle between volcompd and
// volcomp-sim that answers the daemon's requests badly, the way a broken controller, gateway or
// network does. The requests are passed to the simulator (so every write that reaches the
// controller is in its record and checked against the limits there); what comes back is, by mode:
//
//   PassThrough         the simulator's reply as it is (the peer behaves)
//   WrongTransactionId  the reply with another transaction identifier
//   WrongUnitId         the reply from another unit (slave) identifier
//   WrongFunction       the reply with another function code
//   Truncated           the first 1..n-1 bytes of the reply, then nothing
//   Oversized           a reply claiming (and carrying) far more registers than were asked for,
//                       up to the largest frame the MBAP length allows
//   TrailingGarbage     the reply followed by random bytes (they spoil the next transaction)
//   RandomBytes         1..300 random bytes instead of the reply
//   Exception           an exception reply, the code cycling through 0..255 (every code of the
//                       standard, 1..11, and every one outside it)
//   Silent              nothing: requests are swallowed, never passed on, never answered
//   HeldUp              every other write held 8 ms on its way to the simulator (a congested
//                       gateway or network queue), then passed on and answered as it is
//
// The peer listens on a port of its own choosing on 127.0.0.1, accepts one connection at a time
// (a new one replaces the old, as after the daemon's reconnect) and opens one to the simulator for
// each. Random choices come from a seeded generator: a failing run can be repeated.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace volcomp::e2e {

class HostileModbusPeer {
 public:
  enum class Mode {
    PassThrough,
    WrongTransactionId,
    WrongUnitId,
    WrongFunction,
    Truncated,
    Oversized,
    TrailingGarbage,
    RandomBytes,
    Exception,
    Silent,
    HeldUp,
  };

  static const char* name(Mode mode) {
    switch (mode) {
      case Mode::PassThrough:
        return "pass-through";
      case Mode::WrongTransactionId:
        return "wrong transaction id";
      case Mode::WrongUnitId:
        return "wrong unit id";
      case Mode::WrongFunction:
        return "wrong function code";
      case Mode::Truncated:
        return "truncated replies";
      case Mode::Oversized:
        return "oversized replies";
      case Mode::TrailingGarbage:
        return "trailing garbage";
      case Mode::RandomBytes:
        return "random bytes";
      case Mode::Exception:
        return "exception replies";
      case Mode::Silent:
        return "silent";
      case Mode::HeldUp:
        return "writes held up";
    }
    return "?";
  }

  HostileModbusPeer(int simulatorPort, std::uint32_t seed, Mode mode = Mode::PassThrough)
      : simulatorPort_(simulatorPort), random_(seed), mode_(mode) {
    listen_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    ::setsockopt(listen_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    sockaddr_in address = loopback(0);
    if (::bind(listen_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listen_, 4) != 0) {
      throw std::runtime_error("hostile peer: cannot listen");
    }
    socklen_t length = sizeof address;
    ::getsockname(listen_, reinterpret_cast<sockaddr*>(&address), &length);
    port_ = ntohs(address.sin_port);
    if (::pipe2(wake_.data(), O_CLOEXEC) != 0) throw std::runtime_error("hostile peer: pipe");
    thread_ = std::thread([this] { run(); });
  }

  ~HostileModbusPeer() {
    stop_ = true;
    const char byte = 0;
    (void)!::write(wake_[1], &byte, 1);
    thread_.join();
    closeSession();
    ::close(listen_);
    ::close(wake_[0]);
    ::close(wake_[1]);
  }

  HostileModbusPeer(const HostileModbusPeer&) = delete;
  HostileModbusPeer& operator=(const HostileModbusPeer&) = delete;

  int port() const noexcept { return port_; }
  void setMode(Mode mode) noexcept { mode_ = mode; }
  /// Requests received from the daemon, connections accepted so far.
  std::uint64_t requests() const noexcept { return requests_; }
  std::uint64_t connections() const noexcept { return connections_; }

 private:
  static sockaddr_in loopback(int port) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return address;
  }

  void closeSession() {
    if (client_ >= 0) ::close(client_);
    if (upstream_ >= 0) ::close(upstream_);
    client_ = upstream_ = -1;
    pending_.clear();
  }

  void run() {
    while (!stop_) {
      std::array<pollfd, 3> fds{pollfd{wake_[0], POLLIN, 0}, pollfd{listen_, POLLIN, 0},
                                pollfd{client_, POLLIN, 0}};
      if (::poll(fds.data(), client_ >= 0 ? 3 : 2, 1000) <= 0) continue;
      if (fds[0].revents != 0) break;
      if (fds[1].revents & POLLIN) accept();
      if (client_ >= 0 && (fds[2].revents & (POLLIN | POLLHUP | POLLERR))) serve();
    }
  }

  void accept() {
    const int fd = ::accept4(listen_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) return;
    closeSession();
    client_ = fd;
    ++connections_;
    upstream_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const sockaddr_in address = loopback(simulatorPort_);
    if (::connect(upstream_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
      closeSession();
      return;
    }
    const int one = 1;
    ::setsockopt(client_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    ::setsockopt(upstream_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }

  /// Reads what the daemon sent; handles each complete MBAP frame.
  void serve() {
    std::array<std::uint8_t, 4096> buffer{};
    const ssize_t n = ::read(client_, buffer.data(), buffer.size());
    if (n <= 0) {
      closeSession();
      return;
    }
    pending_.insert(pending_.end(), buffer.begin(), buffer.begin() + n);
    while (pending_.size() >= 7) {
      const std::size_t length = 6u + ((pending_[4] << 8) | pending_[5]);
      if (pending_.size() < length) break;
      const std::vector<std::uint8_t> request(pending_.begin(),
                                              pending_.begin() + static_cast<long>(length));
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<long>(length));
      ++requests_;
      handle(request);
      if (client_ < 0) return;
    }
  }

  void handle(const std::vector<std::uint8_t>& request) {
    const Mode mode = mode_;
    if (mode == Mode::Silent) return;
    if (mode == Mode::HeldUp && isWrite(request) && (writes_++ % 2) == 0) {
      pollfd none{};
      ::poll(&none, 0, kHoldMs);  // the delay is the fault being injected
    }
    std::vector<std::uint8_t> reply;
    if (!forward(request, reply)) {
      closeSession();
      return;
    }
    corrupt(mode, request, reply);
    sendAll(reply);
  }

  static bool isWrite(const std::vector<std::uint8_t>& request) {
    const std::uint8_t function = request.size() > 7 ? request[7] : 0;
    return function == 0x06 || function == 0x10 || function == 0x17;
  }

  /// Passes the request to the simulator and reads its reply frame.
  bool forward(const std::vector<std::uint8_t>& request, std::vector<std::uint8_t>& reply) {
    if (!writeAll(upstream_, request)) return false;
    reply.clear();
    std::size_t want = 7;
    while (reply.size() < want) {
      pollfd fd{upstream_, POLLIN, 0};
      if (::poll(&fd, 1, 2000) <= 0) return false;
      std::array<std::uint8_t, 512> chunk{};
      const ssize_t n =
          ::read(upstream_, chunk.data(), std::min(chunk.size(), want - reply.size()));
      if (n <= 0) return false;
      reply.insert(reply.end(), chunk.begin(), chunk.begin() + n);
      if (reply.size() >= 7) want = 6u + ((reply[4] << 8) | reply[5]);
    }
    return true;
  }

  std::uint8_t randomByte() { return static_cast<std::uint8_t>(random_() & 0xFF); }
  std::size_t randomIn(std::size_t low, std::size_t high) {
    return low + static_cast<std::size_t>(random_() % (high - low + 1));
  }

  void corrupt(Mode mode, const std::vector<std::uint8_t>& request,
               std::vector<std::uint8_t>& reply) {
    switch (mode) {
      case Mode::PassThrough:
      case Mode::Silent:
      case Mode::HeldUp:
        return;
      case Mode::WrongTransactionId:
        reply[0] ^= 0x5A;
        reply[1] ^= static_cast<std::uint8_t>(1 + randomByte() % 255);
        return;
      case Mode::WrongUnitId:
        reply[6] = static_cast<std::uint8_t>(reply[6] + 1 + randomByte() % 254);
        return;
      case Mode::WrongFunction:
        reply[7] = reply[7] == 0x03 ? 0x04 : 0x03;
        return;
      case Mode::Truncated:
        reply.resize(randomIn(1, reply.size() - 1));
        return;
      case Mode::Oversized: {
        // Byte count and MBAP length agree with each other and with the data sent, all far
        // beyond what was asked for (a PDU may be 253 bytes; 252 is the byte count's maximum
        // that the MBAP length can still carry).
        const std::uint8_t count = static_cast<std::uint8_t>(randomIn(200, 252) & ~1u);
        reply.resize(9);
        reply[7] = request[7];
        reply[8] = count;
        for (std::uint8_t i = 0; i < count; ++i) reply.push_back(randomByte());
        const std::size_t length = reply.size() - 6;
        reply[4] = static_cast<std::uint8_t>(length >> 8);
        reply[5] = static_cast<std::uint8_t>(length & 0xFF);
        return;
      }
      case Mode::TrailingGarbage: {
        const std::size_t extra = randomIn(1, 300);
        for (std::size_t i = 0; i < extra; ++i) reply.push_back(randomByte());
        return;
      }
      case Mode::RandomBytes: {
        reply.resize(randomIn(1, 300));
        for (std::uint8_t& b : reply) b = randomByte();
        return;
      }
      case Mode::Exception: {
        reply.resize(9);
        reply[4] = 0;
        reply[5] = 3;
        reply[7] = static_cast<std::uint8_t>(request[7] | 0x80);
        reply[8] = static_cast<std::uint8_t>(exceptionCode_++);
        return;
      }
    }
  }

  void sendAll(const std::vector<std::uint8_t>& bytes) {
    if (!writeAll(client_, bytes)) closeSession();
  }

  static bool writeAll(int fd, const std::vector<std::uint8_t>& bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }

  static constexpr int kHoldMs = 8;

  int simulatorPort_;
  int port_ = 0;
  int listen_ = -1;
  int client_ = -1;
  int upstream_ = -1;
  std::array<int, 2> wake_{-1, -1};
  std::vector<std::uint8_t> pending_;
  std::mt19937 random_;
  std::atomic<Mode> mode_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> requests_{0};
  std::uint64_t writes_ = 0;
  std::atomic<std::uint64_t> connections_{0};
  unsigned exceptionCode_ = 0;
  std::thread thread_;
};

}  // namespace volcomp::e2e
