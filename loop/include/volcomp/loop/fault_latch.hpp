#pragma once
/// The fault latch (docs/daemon.md "States", the fault row; `fault_latch` in the configuration):
/// a fault stays after its cause is gone, until the controller acknowledges it.
///
///   latch        a latchable fault (every fault but a failed transaction, status.hpp) of a cycle
///                is held while latching is on; a newer one replaces it;
///   hold         a cycle without a fault of its own gets the held one (FAULT bit and its code,
///                LATCHED), so the offsets keep ramping out;
///   acknowledge  a rising edge of the fault-ack input or a falling edge of the enable input (the
///                enable toggle) between two successful reads clears what is held. A failed read
///                says nothing about the inputs and is no edge.
/// A cause still present when acknowledged latches again in the same cycle. No clock, no units:
/// edges are counted per read. noexcept.

#include "volcomp/loop/status.hpp"

namespace volcomp::loop {

class FaultLatch {
 public:
  /// Takes the inputs of a read as the reference for the next edge without acting on them (at
  /// synchronisation: a toggle while the loop was not reading acknowledges nothing).
  void seed(bool enable, bool faultAck) noexcept;
  /// The inputs of a successful read (`faultAck` false when the input is not mapped): clears the
  /// held fault on a rising fault-ack or a falling enable. Returns true when it cleared one.
  bool acknowledge(bool enable, bool faultAck) noexcept;
  /// The fault of a cycle through the latch: a latchable `fault` is held when `latching` is on
  /// and returned as it is; a cycle without a fault (None) gets the held one (None when none).
  FaultCode apply(FaultCode fault, bool latching) noexcept;
  /// Forgets the held fault (latching switched off by new settings).
  void release() noexcept { held_ = FaultCode::None; }

  /// The fault held until acknowledged, None when nothing is held.
  FaultCode held() const noexcept { return held_; }
  bool holding() const noexcept { return held_ != FaultCode::None; }

 private:
  FaultCode held_ = FaultCode::None;
  bool lastEnable_ = false;
  bool lastAck_ = false;
};

}  // namespace volcomp::loop
