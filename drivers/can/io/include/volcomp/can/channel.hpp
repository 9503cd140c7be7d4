#pragma once
/// One SocketCAN raw socket on an Asio io_context: opens and binds it to an interface, keeps one
/// asynchronous receive pending (no thread of its own: frames are handled whenever the owner runs
/// or polls the io_context), and sends frames without ever blocking.

#include <net/if.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <system_error>

#include <asio/io_context.hpp>

#include "volcomp/can/frame.hpp"
#include "volcomp/can/protocol.hpp"

namespace volcomp::can {

/// What a channel delivers. Called from the io_context; must not throw.
class FrameReceiver {
 public:
  /// A well-formed data frame.
  virtual void onFrame(const Frame& frame) noexcept = 0;
  /// An error frame: `errorClass` holds the CAN_ERR_* class bits, `frame.data` the details.
  virtual void onErrorFrame(std::uint32_t errorClass, const Frame& frame) noexcept = 0;
  /// A frame that is not a valid classical or FD data frame (bad size or DLC, remote request).
  virtual void onMalformed() noexcept = 0;
  /// The socket failed (already mapped: network_down for interface loss). No further receives.
  virtual void onReceiveError(std::error_code ec) noexcept = 0;

 protected:
  ~FrameReceiver() = default;
};

/// Maps a socket error to the codes the daemon understands: interface gone or down (ENETDOWN,
/// ENODEV, ENXIO) -> std::errc::network_down; transmit queue full (ENOBUFS, EAGAIN) ->
/// Errc::TxDropped; anything else unchanged.
std::error_code mapSocketError(std::error_code ec) noexcept;

/// What one datagram of a raw CAN socket is, handed to `receiver`: `bytes` is what the receive
/// returned (CAN_MTU for a classical frame, CANFD_MTU for an FD frame when `fd`), `datagram` its
/// contents. Error frames go to onErrorFrame; remote requests, payload lengths the size does not
/// allow and any other size to onMalformed; the rest, well formed, to onFrame. noexcept and
/// allocation-free; what Channel does with every receive (and what the fuzz target feeds).
void deliverDatagram(const canfd_frame& datagram, std::size_t bytes, bool fd,
                     FrameReceiver& receiver) noexcept;

class Channel {
 public:
  Channel(asio::io_context& io, FrameReceiver& receiver);
  ~Channel();
  Channel(const Channel&) = delete;
  Channel& operator=(const Channel&) = delete;

  /// Opens a CAN_RAW socket on `interfaceName` (which must exist and be up, else network_down),
  /// with CAN FD frames when `fd`, the receive `filters` (all frames when empty) and the error
  /// classes `errorMask` (CAN_ERR_*), and starts receiving.
  std::error_code open(const std::string& interfaceName, bool fd,
                       std::span<const can_filter> filters, can_err_mask_t errorMask) noexcept;
  void close() noexcept;
  bool isOpen() const noexcept { return socket_.is_open(); }

  /// True when the interface reports a carrier (IFF_RUNNING). A CAN controller's kernel driver
  /// takes the carrier down when the controller goes bus-off and up again when it restarts, so
  /// this is the bus-off state at the source, whatever error frames were lost on the way.
  bool carrierUp() noexcept;

  /// Frames the kernel dropped because this socket's receive queue was full, counted since the
  /// socket was opened (SO_MEMINFO, modulo 2^32); 0 when closed or unknown. Error frames are
  /// among what a full queue drops, so a state report may be missing when this has grown.
  std::uint32_t droppedFrames() noexcept;

  /// Sends one frame without blocking (see mapSocketError for the errors). `bitrateSwitch` sets
  /// BRS on CAN FD frames. noexcept and allocation-free.
  std::error_code send(const Frame& frame, bool bitrateSwitch = false) noexcept;

 private:
  void receive() noexcept;
  void handle(std::size_t bytes) noexcept;

  RawProtocol::socket socket_;
  FrameReceiver& receiver_;
  canfd_frame rx_{};
  bool fd_ = false;
  char interfaceName_[IFNAMSIZ] = {};
};

}  // namespace volcomp::can
