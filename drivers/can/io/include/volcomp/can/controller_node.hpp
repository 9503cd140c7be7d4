#pragma once
/// The controller's side of the CAN link, for the simulator (volcomp-sim) and tests: it sends the
/// input frames (positions, enable, homed, sequence counter, read-back) the daemon reads, answers
/// SYNC frames, and assembles the output frames (offsets, status, heartbeat) the daemon writes.
/// It uses the same resolved layout as the daemon, on the caller's io_context (no thread).

#include <cstdint>
#include <functional>
#include <vector>

#include <asio/io_context.hpp>

#include "volcomp/can/channel.hpp"
#include "volcomp/can/layout.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::can {

class CanControllerNode final : private FrameReceiver {
 public:
  CanControllerNode(asio::io_context& io, CanLayout layout);

  /// Opens the socket on the layout's interface (network_down when missing or down).
  std::error_code open() noexcept;
  void close() noexcept;
  bool isOpen() const noexcept { return channel_.isOpen(); }

  /// Sends every input frame for `sample`, each carrying `sequence` (modulo 2^length) in its
  /// sequence counter. Positions that do not fit their signals fail before anything is sent.
  std::error_code publish(const loop::AxisSample& sample, std::uint64_t sequence) noexcept;

  /// Called for every SYNC frame received (sync trigger); usually calls publish().
  void setSyncHandler(std::function<void()> handler) { onSync_ = std::move(handler); }
  /// Called with every complete command (each output frame received once since the last one).
  void setCommandHandler(std::function<void(const loop::OffsetCommand&)> handler) {
    onCommand_ = std::move(handler);
  }

  std::uint64_t commandsReceived() const noexcept { return commands_; }
  const loop::OffsetCommand& lastCommand() const noexcept { return last_; }
  std::uint64_t malformedFrames() const noexcept { return malformed_; }
  std::uint64_t syncsReceived() const noexcept { return syncs_; }
  /// The receive failed (interface down): reopen with open().
  bool receiveFailed() const noexcept { return receiveFailed_; }

 private:
  void onFrame(const Frame& frame) noexcept override;
  void onErrorFrame(std::uint32_t, const Frame&) noexcept override {}
  void onMalformed() noexcept override { ++malformed_; }
  void onReceiveError(std::error_code) noexcept override { receiveFailed_ = true; }

  CanLayout layout_;
  Channel channel_;
  std::vector<can_filter> filters_;
  std::vector<Frame> txFrames_;
  std::vector<bool> fresh_;
  loop::OffsetCommand pending_;
  loop::OffsetCommand last_;
  std::function<void()> onSync_;
  std::function<void(const loop::OffsetCommand&)> onCommand_;
  std::uint64_t commands_ = 0;
  std::uint64_t malformed_ = 0;
  std::uint64_t syncs_ = 0;
  bool receiveFailed_ = false;
};

}  // namespace volcomp::can
