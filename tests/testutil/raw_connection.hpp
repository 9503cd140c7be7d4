#pragma once
// A raw TCP connection for tests that play a hostile or broken peer (bytes as they are, no
// protocol library), and Modbus/TCP request framing for it.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

namespace volcomp::testutil {

using Bytes = std::vector<std::uint8_t>;
using std::chrono::milliseconds;

/// A TCP connection that sends and receives raw bytes.
class RawConnection {
 public:
  explicit RawConnection(std::uint16_t port)
      : fd_(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~RawConnection() { ::close(fd_); }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool connected() const { return connected_; }
  /// The port this end of the connection was given.
  std::uint16_t localPort() const {
    sockaddr_in addr{};
    socklen_t len = sizeof addr;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
    return ntohs(addr.sin_port);
  }
  bool send(const Bytes& bytes) {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(bytes.size());
  }
  /// Up to `n` bytes, waiting at most `timeout` for them; fewer when the peer closed or the
  /// time ran out.
  Bytes receive(std::size_t n, milliseconds timeout) {
    Bytes out;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (out.size() < n) {
      const auto left =
          std::chrono::duration_cast<milliseconds>(deadline - std::chrono::steady_clock::now());
      pollfd p{fd_, POLLIN, 0};
      if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
      std::uint8_t buffer[260];
      const ssize_t got = ::recv(fd_, buffer, std::min(sizeof buffer, n - out.size()), 0);
      if (got <= 0) break;
      out.insert(out.end(), buffer, buffer + got);
    }
    return out;
  }
  /// True when the server closes the connection within `timeout`.
  bool closedByServer(milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    std::uint8_t byte = 0;
    return ::recv(fd_, &byte, 1, 0) <= 0;
  }

 private:
  int fd_;
  bool connected_ = false;
};

/// A Modbus/TCP request: transaction id, unit 1, the PDU.
inline Bytes modbusTcpAdu(std::uint16_t transaction, const Bytes& pdu) {
  Bytes out = {static_cast<std::uint8_t>(transaction >> 8),
               static_cast<std::uint8_t>(transaction & 0xFF),
               0,
               0,
               static_cast<std::uint8_t>((pdu.size() + 1) >> 8),
               static_cast<std::uint8_t>((pdu.size() + 1) & 0xFF),
               1};
  out.insert(out.end(), pdu.begin(), pdu.end());
  return out;
}

}  // namespace volcomp::testutil
