#include "vcan_util.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

namespace volcomp::can::test {

std::string interfaceName() {
  const char* name = std::getenv("VOLCOMP_CAN_IFACE");
  return name && *name ? name : "vcan0";
}

bool setInterfaceUp(const std::string& name, bool up) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return false;
  ifreq request{};
  std::strncpy(request.ifr_name, name.c_str(), IFNAMSIZ - 1);
  bool ok = ::ioctl(fd, SIOCGIFFLAGS, &request) == 0;
  if (ok) {
    if (up)
      request.ifr_flags = static_cast<short>(request.ifr_flags | IFF_UP);
    else
      request.ifr_flags = static_cast<short>(request.ifr_flags & ~IFF_UP);
    ok = ::ioctl(fd, SIOCSIFFLAGS, &request) == 0;
  }
  ::close(fd);
  return ok;
}

PeerSocket::PeerSocket() {
  fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd_ < 0) return;
  const int on = 1;
  can_err_mask_t all = CAN_ERR_MASK;
  ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on);
  ::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &all, sizeof all);
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(if_nametoindex(interfaceName().c_str()));
  if (address.can_ifindex == 0 ||
      ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

PeerSocket::~PeerSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool PeerSocket::send(canid_t rawId, const std::vector<std::uint8_t>& data) {
  can_frame frame{};
  frame.can_id = rawId;
  frame.len = static_cast<std::uint8_t>(data.size());
  std::memcpy(frame.data, data.data(), data.size());
  return ::write(fd_, &frame, CAN_MTU) == static_cast<ssize_t>(CAN_MTU);
}

bool PeerSocket::sendFd(canid_t rawId, const std::vector<std::uint8_t>& data) {
  canfd_frame frame{};
  frame.can_id = rawId;
  frame.len = static_cast<std::uint8_t>(data.size());
  std::memcpy(frame.data, data.data(), data.size());
  return ::write(fd_, &frame, CANFD_MTU) == static_cast<ssize_t>(CANFD_MTU);
}

std::optional<canfd_frame> PeerSocket::receive(std::chrono::milliseconds timeout,
                                               std::size_t* mtu) {
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) != 1) return std::nullopt;
  canfd_frame frame{};
  const ssize_t n = ::read(fd_, &frame, sizeof frame);
  if (n != static_cast<ssize_t>(CAN_MTU) && n != static_cast<ssize_t>(CANFD_MTU))
    return std::nullopt;
  if (mtu) *mtu = static_cast<std::size_t>(n);
  return frame;
}

std::optional<canfd_frame> PeerSocket::receiveId(canid_t rawId, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    auto frame = receive(left);
    if (frame && frame->can_id == rawId) return frame;
  }
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

OutputReader::OutputReader(const std::string& command) {
  // The shell prints the child's pid first, so that the destructor can end exactly that process.
  const std::string script = "exec 2>&1; " + command + " & echo PID:$!; wait";
  pipe_ = ::popen(script.c_str(), "r");
  if (!pipe_) return;
  const auto first = line(std::chrono::seconds(5));
  if (first && first->rfind("PID:", 0) == 0) pid_ = std::atoi(first->c_str() + 4);
}

OutputReader::~OutputReader() {
  if (pid_ > 0) ::kill(pid_, SIGTERM);
  if (pipe_) ::pclose(pipe_);
}

std::optional<std::string> OutputReader::line(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    const std::size_t newline = buffer_.find('\n');
    if (newline != std::string::npos) {
      std::string text = buffer_.substr(0, newline);
      buffer_.erase(0, newline + 1);
      return text;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{::fileno(pipe_), POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) != 1) continue;
    char chunk[256];
    const ssize_t n = ::read(::fileno(pipe_), chunk, sizeof chunk);
    if (n <= 0) return std::nullopt;
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

}  // namespace volcomp::can::test
