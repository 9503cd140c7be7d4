#pragma once
/// SocketCAN as an Asio protocol (after the canary library): `RawProtocol::socket` is an
/// asio::basic_raw_socket over PF_CAN / SOCK_RAW / CAN_RAW, so every synchronous and asynchronous
/// socket operation of Asio works on a CAN socket and runs on an io_context like any other I/O.
/// The endpoint is a sockaddr_can naming the interface by index.

#include <cstddef>
#include <string>
#include <system_error>

#include <linux/can.h>
#include <linux/can/raw.h>
#include <sys/socket.h>

#include <asio/basic_raw_socket.hpp>
#include <asio/detail/socket_option.hpp>

namespace volcomp::can {

class Endpoint;

class RawProtocol {
 public:
  using endpoint = Endpoint;
  using socket = asio::basic_raw_socket<RawProtocol>;
  int family() const noexcept { return PF_CAN; }
  int type() const noexcept { return SOCK_RAW; }
  int protocol() const noexcept { return CAN_RAW; }
};

class Endpoint {
 public:
  using protocol_type = RawProtocol;
  using data_type = asio::detail::socket_addr_type;

  Endpoint() noexcept { address_.can_family = AF_CAN; }
  /// Interface index from if_nametoindex (0 = all CAN interfaces, receive only).
  explicit Endpoint(int interfaceIndex) noexcept : Endpoint() {
    address_.can_ifindex = interfaceIndex;
  }
  protocol_type protocol() const noexcept { return {}; }
  data_type* data() noexcept { return reinterpret_cast<data_type*>(&address_); }
  const data_type* data() const noexcept { return reinterpret_cast<const data_type*>(&address_); }
  std::size_t size() const noexcept { return sizeof(address_); }
  void resize(std::size_t) noexcept {}
  std::size_t capacity() const noexcept { return sizeof(address_); }
  int interfaceIndex() const noexcept { return address_.can_ifindex; }

 private:
  sockaddr_can address_{};
};

/// CAN_RAW_FD_FRAMES: receive and send CAN FD frames (struct canfd_frame, 72 bytes).
using FdFramesOption = asio::detail::socket_option::boolean<SOL_CAN_RAW, CAN_RAW_FD_FRAMES>;

/// A socket option whose value is a plain object or array (filters, error mask).
template <int Level, int Name, typename T, std::size_t N = 1>
class ValueOption {
 public:
  ValueOption() = default;
  explicit ValueOption(const T* values, std::size_t count) noexcept : count_(count) {
    for (std::size_t i = 0; i < count && i < N; ++i) values_[i] = values[i];
  }
  template <typename Protocol>
  int level(const Protocol&) const noexcept {
    return Level;
  }
  template <typename Protocol>
  int name(const Protocol&) const noexcept {
    return Name;
  }
  template <typename Protocol>
  const void* data(const Protocol&) const noexcept {
    return values_;
  }
  template <typename Protocol>
  std::size_t size(const Protocol&) const noexcept {
    return count_ * sizeof(T);
  }

 private:
  T values_[N]{};
  std::size_t count_ = 0;
};

/// CAN_RAW_ERR_FILTER: which error classes (CAN_ERR_* bits) are delivered as error frames.
using ErrorFilterOption = ValueOption<SOL_CAN_RAW, CAN_RAW_ERR_FILTER, can_err_mask_t>;
/// CAN_RAW_FILTER with up to 32 (id, mask) pairs.
using FilterOption = ValueOption<SOL_CAN_RAW, CAN_RAW_FILTER, can_filter, 32>;

}  // namespace volcomp::can
