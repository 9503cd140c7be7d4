#include "volcomp/can/channel.hpp"

#include <array>
#include <cerrno>
#include <cstring>

#include <linux/sock_diag.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <asio/buffer.hpp>
#include <asio/error.hpp>

#include "volcomp/can/errors.hpp"

namespace volcomp::can {

std::error_code mapSocketError(std::error_code ec) noexcept {
  // Standalone Asio reports errno values in its own "asio.system" category.
  if (!ec || (ec.category() != std::system_category() &&
              ec.category() != asio::error::get_system_category()))
    return ec;
  switch (ec.value()) {
    case ENETDOWN:
    case ENODEV:
    case ENXIO:
      return std::make_error_code(std::errc::network_down);
    case ENOBUFS:
    case EAGAIN:
      return Errc::TxDropped;
    default:
      return ec;
  }
}

Channel::Channel(asio::io_context& io, FrameReceiver& receiver)
    : socket_(io), receiver_(receiver) {}

Channel::~Channel() {
  close();
}

std::error_code Channel::open(const std::string& interfaceName, bool fd,
                              std::span<const can_filter> filters,
                              can_err_mask_t errorMask) noexcept {
  close();
  const unsigned index = if_nametoindex(interfaceName.c_str());
  if (index == 0) return std::make_error_code(std::errc::network_down);
  std::error_code ec;
  socket_.open(RawProtocol{}, ec);
  if (ec) return ec;
  // Binding to an interface that is down succeeds but nothing would ever arrive: report the
  // link as down so that the daemon keeps retrying with its backoff.
  ifreq request{};
  std::strncpy(request.ifr_name, interfaceName.c_str(), IFNAMSIZ - 1);
  if (::ioctl(socket_.native_handle(), SIOCGIFFLAGS, &request) != 0 ||
      (request.ifr_flags & IFF_UP) == 0) {
    close();
    return std::make_error_code(std::errc::network_down);
  }
  fd_ = fd;
  std::memcpy(interfaceName_, request.ifr_name, IFNAMSIZ);
  if (fd) socket_.set_option(FdFramesOption(true), ec);
  if (!ec && !filters.empty()) socket_.set_option(FilterOption(filters.data(), filters.size()), ec);
  if (!ec) socket_.set_option(ErrorFilterOption(&errorMask, 1), ec);
  if (!ec) socket_.bind(Endpoint(static_cast<int>(index)), ec);
  if (!ec) socket_.non_blocking(true, ec);
  if (ec) {
    close();
    return mapSocketError(ec);
  }
  receive();
  return {};
}

bool Channel::carrierUp() noexcept {
  if (!socket_.is_open()) return false;
  ifreq request{};
  std::memcpy(request.ifr_name, interfaceName_, IFNAMSIZ);
  return ::ioctl(socket_.native_handle(), SIOCGIFFLAGS, &request) == 0 &&
         (request.ifr_flags & IFF_RUNNING) != 0;
}

std::uint32_t Channel::droppedFrames() noexcept {
  if (!socket_.is_open()) return 0;
  std::array<std::uint32_t, SK_MEMINFO_VARS> info{};
  socklen_t size = sizeof info;
  if (::getsockopt(socket_.native_handle(), SOL_SOCKET, SO_MEMINFO, info.data(), &size) != 0 ||
      size < sizeof(std::uint32_t) * (SK_MEMINFO_DROPS + 1))
    return 0;
  return info[SK_MEMINFO_DROPS];
}

void Channel::close() noexcept {
  std::error_code ignored;
  if (socket_.is_open()) socket_.close(ignored);
}

std::error_code Channel::send(const Frame& frame, bool bitrateSwitch) noexcept {
  if (!socket_.is_open()) return std::make_error_code(std::errc::not_connected);
  canfd_frame out{};
  out.can_id =
      frame.extended ? ((frame.id & CAN_EFF_MASK) | CAN_EFF_FLAG) : (frame.id & CAN_SFF_MASK);
  out.len = frame.length;
  std::memcpy(out.data, frame.data.data(), frame.length);
  std::size_t size = CAN_MTU;
  if (frame.fd) {
    out.flags = static_cast<std::uint8_t>(CANFD_FDF | (bitrateSwitch ? CANFD_BRS : 0));
    size = CANFD_MTU;
  }
  std::error_code ec;
  const std::size_t sent = socket_.send(asio::buffer(&out, size), 0, ec);
  if (ec) return mapSocketError(ec);
  if (sent != size) return Errc::TxDropped;
  return {};
}

void Channel::receive() noexcept {
  socket_.async_receive(asio::buffer(&rx_, sizeof rx_),
                        [this](const std::error_code& ec, std::size_t bytes) {
                          if (ec == asio::error::operation_aborted) return;
                          if (ec) {
                            receiver_.onReceiveError(mapSocketError(ec));
                            return;
                          }
                          handle(bytes);
                          if (socket_.is_open()) receive();
                        });
}

void Channel::handle(std::size_t bytes) noexcept {
  deliverDatagram(rx_, bytes, fd_, receiver_);
}

void deliverDatagram(const canfd_frame& datagram, std::size_t bytes, bool fd,
                     FrameReceiver& receiver) noexcept {
  Frame frame;
  const canid_t id = datagram.can_id;
  if (bytes == CAN_MTU) {
    if (datagram.len > kClassicMaxLength) return receiver.onMalformed();
  } else if (bytes == CANFD_MTU && fd) {
    if (!isValidLength(datagram.len, true)) return receiver.onMalformed();
    frame.fd = true;
  } else {
    return receiver.onMalformed();
  }
  frame.extended = (id & CAN_EFF_FLAG) != 0;
  frame.id = frame.extended ? (id & CAN_EFF_MASK) : (id & CAN_SFF_MASK);
  frame.length = datagram.len;
  std::memcpy(frame.data.data(), datagram.data, datagram.len);
  if ((id & CAN_ERR_FLAG) != 0) return receiver.onErrorFrame(id & CAN_ERR_MASK, frame);
  if ((id & CAN_RTR_FLAG) != 0) return receiver.onMalformed();
  receiver.onFrame(frame);
}

}  // namespace volcomp::can
