#pragma once
/// Helpers for the tests that run on a real (virtual) CAN interface: the interface name, a peer
/// socket written with plain SocketCAN calls (independent of the driver under test), interface
/// up/down, and running can-utils (waiting on a condition: tests/testutil/wait_until.hpp).

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <linux/can.h>

namespace volcomp::can::test {

/// The interface the tests use: $VOLCOMP_CAN_IFACE, else "vcan0".
std::string interfaceName();

/// Sets the interface administratively up or down (SIOCSIFFLAGS, needs CAP_NET_ADMIN).
bool setInterfaceUp(const std::string& name, bool up);

/// A raw CAN socket on the test interface that receives everything (FD frames and all error
/// classes included) and sends whatever it is given.
class PeerSocket {
 public:
  PeerSocket();
  ~PeerSocket();
  PeerSocket(const PeerSocket&) = delete;
  PeerSocket& operator=(const PeerSocket&) = delete;

  bool ok() const { return fd_ >= 0; }
  /// Classical frame; `rawId` may carry CAN_EFF_FLAG / CAN_RTR_FLAG / CAN_ERR_FLAG.
  bool send(canid_t rawId, const std::vector<std::uint8_t>& data);
  bool sendFd(canid_t rawId, const std::vector<std::uint8_t>& data);
  /// Next frame (classical or FD) within `timeout`; `mtu` tells which kind arrived.
  std::optional<canfd_frame> receive(std::chrono::milliseconds timeout, std::size_t* mtu = nullptr);
  /// Next frame with this identifier (flags included), skipping others.
  std::optional<canfd_frame> receiveId(canid_t rawId, std::chrono::milliseconds timeout);

 private:
  int fd_ = -1;
};

/// Runs a shell command and returns its exit status (-1 when it could not run).
int run(const std::string& command);

/// A child process (run in the background by sh) whose standard output and error are read line
/// by line with a timeout; it is terminated when the reader goes away.
class OutputReader {
 public:
  explicit OutputReader(const std::string& command);
  ~OutputReader();
  OutputReader(const OutputReader&) = delete;
  OutputReader& operator=(const OutputReader&) = delete;
  bool ok() const { return pipe_ != nullptr; }
  /// The next complete line, or nothing after `timeout`.
  std::optional<std::string> line(std::chrono::milliseconds timeout);

 private:
  FILE* pipe_ = nullptr;
  int pid_ = -1;
  std::string buffer_;
};

}  // namespace volcomp::can::test
