#include "volcomp/loop/fault_latch.hpp"

namespace volcomp::loop {

void FaultLatch::seed(bool enable, bool faultAck) noexcept {
  lastEnable_ = enable;
  lastAck_ = faultAck;
}

bool FaultLatch::acknowledge(bool enable, bool faultAck) noexcept {
  // Edges, not levels: an ack input held high (a stuck button) must not acknowledge every fault
  // that follows.
  const bool acknowledged = holding() && ((faultAck && !lastAck_) || (!enable && lastEnable_));
  if (acknowledged) held_ = FaultCode::None;
  seed(enable, faultAck);
  return acknowledged;
}

FaultCode FaultLatch::apply(FaultCode fault, bool latching) noexcept {
  if (fault != FaultCode::None) {
    if (latching && latchable(fault)) held_ = fault;
    return fault;
  }
  return held_;
}

}  // namespace volcomp::loop
