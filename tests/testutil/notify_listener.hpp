#pragma once
// The service manager's side of sd_notify for tests: a unix datagram socket bound at a path the
// test chooses (pass it to the child as NOTIFY_SOCKET). Datagrams are read with a deadline (poll)
// and kept, so a test can wait for one message and later look at everything received.

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace volcomp::testutil {

class NotifyListener {
 public:
  explicit NotifyListener(std::string path) : path_(std::move(path)) {
    sockaddr_un addr{};
    if (path_.size() >= sizeof addr.sun_path) throw std::runtime_error("socket path too long");
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) throw std::runtime_error("socket(AF_UNIX, SOCK_DGRAM) failed");
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, path_.c_str(), path_.size() + 1);
    ::unlink(path_.c_str());
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
      ::close(fd_);
      throw std::runtime_error("cannot bind " + path_ + ": " + std::strerror(errno));
    }
  }
  ~NotifyListener() {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
  NotifyListener(const NotifyListener&) = delete;
  NotifyListener& operator=(const NotifyListener&) = delete;

  const std::string& path() const noexcept { return path_; }

  /// The next datagram within the timeout, or nullopt.
  std::optional<std::string> receive(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return std::nullopt;
    char buffer[4096];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    if (n < 0) return std::nullopt;
    received_.emplace_back(buffer, static_cast<std::size_t>(n));
    return received_.back();
  }

  /// Receives until a datagram contains `text` as one of its lines; returns its index in
  /// received(), or nullopt at the deadline.
  std::optional<std::size_t> waitFor(const std::string& text, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      const auto message = receive(left);
      if (!message) return std::nullopt;
      if (hasLine(*message, text)) return received_.size() - 1;
    }
  }

  /// Every datagram received so far, in order.
  const std::vector<std::string>& received() const noexcept { return received_; }

  /// Whether `message` has `line` as one of its newline-separated assignments.
  static bool hasLine(const std::string& message, const std::string& line) {
    std::size_t start = 0;
    while (start <= message.size()) {
      const auto end = message.find('\n', start);
      const auto len = (end == std::string::npos ? message.size() : end) - start;
      if (message.compare(start, len, line) == 0) return true;
      if (end == std::string::npos) break;
      start = end + 1;
    }
    return false;
  }

 private:
  std::string path_;
  int fd_ = -1;
  std::vector<std::string> received_;
};

}  // namespace volcomp::testutil
