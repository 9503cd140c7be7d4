#include "volcomp/sim/can_sim_node.hpp"

namespace volcomp::sim {

CanSimNode::CanSimNode(asio::io_context& io, can::CanLayout layout, Callbacks callbacks,
                       std::chrono::microseconds broadcastPeriod)
    : node_(io, layout),
      timer_(io),
      callbacks_(std::move(callbacks)),
      period_(broadcastPeriod),
      broadcast_(layout.trigger == can::Trigger::Broadcast) {
  node_.setSyncHandler([this] { publish(); });
  node_.setCommandHandler([this](const loop::OffsetCommand& command) {
    callbacks_.onWrite(callbacks_.nowS(), command);
  });
}

std::error_code CanSimNode::start() {
  if (auto ec = node_.open()) return ec;
  running_ = true;
  if (broadcast_) {
    timer_.expires_after(period_);
    scheduleBroadcast();
  }
  return {};
}

void CanSimNode::stop() {
  running_ = false;
  timer_.cancel();
  node_.close();
}

void CanSimNode::publish() {
  const loop::AxisSample sample = callbacks_.inputs(callbacks_.nowS());
  const std::uint64_t sequence = sample.hasSequence ? sample.sequence : counter_++;
  if (node_.publish(sample, sequence))
    ++publishErrors_;
  else
    ++published_;
}

void CanSimNode::scheduleBroadcast() {
  // Absolute deadlines: a late wake-up does not shift the following broadcasts.
  timer_.async_wait([this](const std::error_code& ec) {
    if (ec || !running_) return;
    publish();
    timer_.expires_at(timer_.expiry() + period_);
    scheduleBroadcast();
  });
}

}  // namespace volcomp::sim
