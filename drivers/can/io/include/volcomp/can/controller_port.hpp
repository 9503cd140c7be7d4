#pragma once
/// The daemon's CAN transport: a SocketCAN driver implementing volcomp::loop::ControllerPort.
///
/// It owns an Asio io_context with one CAN socket and no thread: read() and write() run the
/// io_context just long enough to drain the socket (and, with the sync trigger, to wait for the
/// controller's answer up to the response timeout), so frames are decoded on the daemon's loop
/// thread with nothing to lock.
///
/// read():  broadcast trigger — returns the newest complete, consistent set of input frames
///          (every input frame received, all with the same sequence counter); StaleInput when it
///          is older than the stale timeout (right after connect() the first read waits up to
///          the stale timeout for the first set). sync trigger — sends the SYNC frame and waits
///          for every input frame; NoResponse after the response timeout.
/// write(): encodes every output frame first (an offset that does not fit its signal fails the
///          whole write, nothing is sent), then sends them back to back without blocking; a full
///          transmit queue drops the frame, counts it and returns TxDropped.
/// Errors:  interface down or gone -> std::errc::network_down (a link error: the socket is
///          closed, connect() reopens it once the interface is up again); error frames reporting
///          bus-off / error-passive -> BusOff / ErrorPassive from read() (write() refuses only on
///          bus-off) until the controller reports error-active or restarted again. Bus-off also
///          ends when the interface has its carrier (the kernel's CAN drivers drop it at bus-off
///          and raise it at the restart) and no bus-off report has come for the stale timeout:
///          a restart report lost to a full receive queue (a flooded bus) does not leave the
///          daemon refusing to write for ever. Error-passive ends likewise without its report
///          when the kernel dropped frames after the passive report (so the report of the way
///          back may be among them), no passive report has come for the stale timeout, and
///          complete input sets have arrived since, the newest fresh: the controller talks
///          again. With nothing dropped, a controller that stays passive stays a fault.
///          Frames too short for their signals, undecodable values (NaN float, outside the DBC
///          range), remote requests and bad sizes are ignored and counted.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <asio/io_context.hpp>

#include "volcomp/can/channel.hpp"
#include "volcomp/can/layout.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::can {

/// Controller error state as last reported by error frames.
enum class BusState : std::uint8_t { ErrorActive, ErrorWarning, ErrorPassive, BusOff };

struct CanStats {
  std::uint64_t framesReceived = 0;  ///< data frames accepted (decoded into an input slot)
  std::uint64_t framesSent = 0;
  std::uint64_t malformedFrames = 0;  ///< too short, undecodable, bad size/DLC, remote request
  std::uint64_t unknownFrames = 0;    ///< well-formed data frames that are not inputs
  std::uint64_t txDropped = 0;        ///< frames dropped because the transmit queue was full
  std::uint64_t errorFrames = 0;
  std::uint64_t busOffEvents = 0;
  std::uint64_t busOffEndedByCarrier = 0;  ///< bus-off left without a restart report (see above)
  std::uint64_t errorPassiveEvents = 0;
  std::uint64_t errorPassiveEndedAfterDrops = 0;  ///< left without its report (see above)
  std::uint64_t receiveQueueDrops = 0;  ///< frames the kernel dropped from a full receive queue
  std::uint64_t completeSets = 0;       ///< complete, consistent input sets assembled
  std::uint64_t discardedFrames = 0;    ///< input frames superseded by a newer sequence counter
  std::uint64_t linkErrors = 0;         ///< link lost: interface down / gone, socket failed
};

class CanControllerPort final : public loop::ControllerPort, private FrameReceiver {
 public:
  explicit CanControllerPort(CanLayout layout);
  ~CanControllerPort() override;

  std::error_code connect() noexcept override;
  void disconnect() noexcept override;
  bool connected() const noexcept override;
  std::error_code read(loop::AxisSample& out) noexcept override;
  std::error_code write(const loop::OffsetCommand& command) noexcept override;

  /// Takes one datagram as if the socket had received it (deliverDatagram with the layout's FD
  /// setting): how the fuzz target and tests feed frames without a CAN interface.
  void receive(const canfd_frame& datagram, std::size_t bytes) noexcept;

  const CanStats& stats() const noexcept { return stats_; }
  BusState busState() const noexcept { return busState_; }
  /// The socket error that last ended the link (for the log line), empty before any.
  std::error_code lastLinkError() const noexcept { return lastLinkError_; }
  const CanLayout& layout() const noexcept { return layout_; }
  /// The input frames of the last complete set (in layout_.inputFrames order) and the output
  /// frames of the last write, raw, for commissioning (decode them with the signal codec).
  const std::vector<Frame>& lastInputFrames() const noexcept { return latestFrames_; }
  const std::vector<Frame>& lastOutputFrames() const noexcept { return txFrames_; }

 private:
  struct InputSlot {
    bool fresh = false;  ///< received since the last complete set (or the last SYNC)
    std::uint64_t sequence = 0;
    std::array<double, kFieldCount> values{};
    Frame frame;  ///< the frame the values came from
  };

  void onFrame(const Frame& frame) noexcept override;
  void onErrorFrame(std::uint32_t errorClass, const Frame& frame) noexcept override;
  void onMalformed() noexcept override;
  void onReceiveError(std::error_code ec) noexcept override;

  void pump() noexcept;
  void countDrops() noexcept;
  void drained() noexcept;
  void noteStateReport() noexcept;
  void completeIfConsistent(std::size_t newest) noexcept;
  std::error_code linkDown() noexcept;
  std::error_code busError() noexcept;
  std::error_code waitForSet(std::chrono::steady_clock::time_point deadline) noexcept;

  CanLayout layout_;
  asio::io_context io_;
  Channel channel_;
  std::vector<can_filter> filters_;
  std::vector<InputSlot> slots_;
  std::array<std::size_t, kFieldCount> fieldSlot_{};
  std::vector<Frame> txFrames_;
  std::vector<Frame> latestFrames_;  ///< one per input frame, sized once
  loop::AxisSample latest_;
  bool haveSet_ = false;
  bool linkLost_ = false;
  std::chrono::steady_clock::time_point setTime_{};
  std::chrono::steady_clock::time_point connectTime_{};
  std::chrono::steady_clock::time_point lastStateReport_{};  ///< bus-off or error-passive
  std::uint32_t socketDrops_ = 0;         ///< the open socket's own drop counter, last read
  std::uint64_t dropsAfterDrain_ = 0;     ///< receiveQueueDrops when the last drain ended
  std::uint64_t dropsAtStateReport_ = 0;  ///< dropsAfterDrain_ before the drain with that report
  BusState busState_ = BusState::ErrorActive;
  std::error_code lastLinkError_;
  CanStats stats_;
};

}  // namespace volcomp::can
