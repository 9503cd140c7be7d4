#include "volcomp/sim/can_server.hpp"

#include <asio/post.hpp>
#include <iostream>
#include <system_error>

namespace volcomp::sim {

CanServer::CanServer(can::CanLayout layout, Machine& machine, std::function<double()> now,
                     std::chrono::microseconds broadcastPeriod)
    : interface_(layout.interfaceName),
      machine_(machine),
      now_(std::move(now)),
      work_(asio::make_work_guard(io_)),
      node_(io_, std::move(layout),
            {[this](double t) { return machine_.inputs(t); },
             [this](double t, const loop::OffsetCommand& c) { machine_.onWrite(t, c); },
             [this] { return now_(); }},
            broadcastPeriod) {}

CanServer::~CanServer() {
  stop();
}

void CanServer::start() {
  // Opened before the thread exists, so that a missing interface is reported to the caller.
  if (const std::error_code ec = node_.start()) {
    throw std::system_error(ec, "cannot open CAN interface " + interface_);
  }
  machine_.onSessionStart(now_());
  open_ = true;
  thread_ = std::thread([this] { io_.run(); });
}

void CanServer::openNode() noexcept {
  if (!open_) {
    if (node_.start()) return;  // still down: update() retries
    ++reopens_;
    machine_.onSessionStart(now_());
    open_ = true;
    std::cerr << "volcomp-sim: CAN node on " << interface_ << " open again\n";
  }
}

void CanServer::closeNode() noexcept {
  if (open_) {
    node_.stop();
    open_ = false;
  }
}

void CanServer::update(double tS) {
  if (!thread_.joinable() || queued_) return;
  const TransportFault fault = machine_.transportFault(tS);
  const bool silent = fault.stall || fault.linkDown;
  if (silent && open_) {
    queued_ = true;
    asio::post(io_, [this] {
      closeNode();
      queued_ = false;
    });
  } else if (!silent && tS >= nextCheckS_) {
    // Every 100 ms: reopen a closed node, or one whose receive failed (interface went down).
    nextCheckS_ = tS + 0.1;
    queued_ = true;
    asio::post(io_, [this] {
      if (open_ && node_.node().receiveFailed()) {
        std::cerr << "volcomp-sim: CAN receive on " << interface_ << " failed; reopening\n";
        closeNode();
      }
      openNode();
      queued_ = false;
    });
  }
}

void CanServer::stop() noexcept {
  if (!thread_.joinable()) return;
  // The node's socket and timer belong to the io thread: stop it there, then let run() return.
  asio::post(io_, [this] { closeNode(); });
  work_.reset();
  thread_.join();
}

std::string CanServer::listeningLine() const {
  return "LISTENING can " + interface_;
}

nlohmann::json CanServer::counters() const {
  return {{"published", node_.published()},
          {"publish_errors", node_.publishErrors()},
          {"commands", node_.node().commandsReceived()},
          {"malformed_frames", node_.node().malformedFrames()},
          {"syncs", node_.node().syncsReceived()},
          {"reopens", reopens_}};
}

}  // namespace volcomp::sim
