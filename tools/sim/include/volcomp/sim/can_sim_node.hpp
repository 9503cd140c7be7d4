#pragma once
/// The CAN face of a simulated controller (volcomp-sim, tests): a CanControllerNode driven by two
/// callbacks into the machine model, on the caller's io_context (no thread of its own).
/// - broadcast trigger: every `broadcastPeriod` it sends the input frames of inputs(t), with the
///   sample's life counter (or its own counter when the sample has none) as sequence counter;
/// - sync trigger: it answers every SYNC frame with the input frames of inputs(t);
/// - every complete set of output frames is handed to onWrite(t, command).
/// Time t is seconds from `nowS`.
///
/// Wiring (CanServer does this for volcomp-sim):
///   asio::io_context io;
///   sim::CanSimNode node(io, layout,
///       {.inputs = [&](double t) { return machine.inputs(t); },
///        .onWrite = [&](double t, const loop::OffsetCommand& c) { machine.onWrite(t, c); },
///        .nowS = [&] { return secondsSinceStart(); }},
///       std::chrono::milliseconds(1));
///   node.start();  // then run io (the sim's thread); stop() before the io_context goes away

#include <chrono>
#include <cstdint>
#include <functional>

#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>

#include "volcomp/can/controller_node.hpp"
#include "volcomp/can/layout.hpp"

namespace volcomp::sim {

class CanSimNode {
 public:
  struct Callbacks {
    std::function<loop::AxisSample(double tS)> inputs;
    std::function<void(double tS, const loop::OffsetCommand&)> onWrite;
    std::function<double()> nowS;
  };

  CanSimNode(asio::io_context& io, can::CanLayout layout, Callbacks callbacks,
             std::chrono::microseconds broadcastPeriod);

  /// Opens the socket and, with the broadcast trigger, starts sending. network_down when the
  /// interface is missing or down.
  std::error_code start();
  /// Stops sending and closes the socket (call on the io_context's thread, or when it is not
  /// running).
  void stop();

  std::uint64_t published() const noexcept { return published_; }
  std::uint64_t publishErrors() const noexcept { return publishErrors_; }
  const can::CanControllerNode& node() const noexcept { return node_; }

 private:
  void publish();
  void scheduleBroadcast();

  can::CanControllerNode node_;
  asio::steady_timer timer_;
  Callbacks callbacks_;
  std::chrono::microseconds period_;
  bool broadcast_;
  bool running_ = false;
  std::uint64_t counter_ = 0;
  std::uint64_t published_ = 0;
  std::uint64_t publishErrors_ = 0;
};

}  // namespace volcomp::sim
