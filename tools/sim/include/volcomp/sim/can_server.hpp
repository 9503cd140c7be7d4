#pragma once
/// The simulated controller's CAN face: a CanSimNode (can_sim_node.hpp) on its own io_context
/// thread, sending the input frames of Machine::inputs(t) (broadcast every `broadcastPeriod`, or as
/// the answer to each SYNC frame) and handing every complete set of output frames to
/// Machine::onWrite(t, ...). Same layout as the daemon's transport section.
///
/// Faults from Machine::transportFault, applied by update(t) (call it every simulator tick):
/// `stall` and `drop-link` both make the node silent — its socket is closed, so it neither sends
/// input frames nor answers SYNC nor receives writes — and it reopens when the fault ends (a CAN
/// bus has no connection to drop; taking the interface itself down needs CAP_NET_ADMIN and is
/// `ip link set DEV down`, outside the simulator). Modbus exception replies have no CAN
/// equivalent. When the interface went down (the node's receive failed) or an open failed, the
/// node is reopened every 100 ms until it succeeds; each reopen counts as a new session.

#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "volcomp/can/layout.hpp"
#include "volcomp/sim/can_sim_node.hpp"
#include "volcomp/sim/machine.hpp"

namespace volcomp::sim {

class CanServer {
 public:
  /// `now` returns the machine time in seconds (monotonic).
  CanServer(can::CanLayout layout, Machine& machine, std::function<double()> now,
            std::chrono::microseconds broadcastPeriod);
  ~CanServer();
  CanServer(const CanServer&) = delete;
  CanServer& operator=(const CanServer&) = delete;

  /// Opens the socket on the layout's interface and starts the io thread. Throws
  /// std::system_error (network_down when the interface is missing or down).
  void start();
  /// Applies the machine's transport faults at time t (silences or reopens the node); called
  /// from one thread (the simulator's main loop).
  void update(double tS);
  /// Stops the node on its thread, then joins the thread (idempotent).
  void stop() noexcept;

  /// "LISTENING can INTERFACE".
  std::string listeningLine() const;
  /// The node's counters (valid after stop()): published, publish_errors, commands,
  /// malformed_frames, syncs, reopens.
  nlohmann::json counters() const;

 private:
  /// On the io thread.
  void openNode() noexcept;
  void closeNode() noexcept;

  const std::string interface_;
  Machine& machine_;
  const std::function<double()> now_;
  asio::io_context io_;
  asio::executor_work_guard<asio::io_context::executor_type> work_;
  CanSimNode node_;
  std::thread thread_;

  // Main thread only.
  double nextCheckS_ = 0.0;
  // Written on the io thread, read by update().
  std::atomic<bool> open_{false};
  std::atomic<bool> queued_{false};  // an open/close/check is queued on the io thread
  std::uint64_t reopens_ = 0;        // io thread
};

}  // namespace volcomp::sim
