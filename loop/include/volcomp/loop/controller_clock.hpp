#pragma once
/// The controller's sample timestamp mapped onto the daemon's clock (latency compensation with a
/// timestamp register, docs/daemon.md "Latency compensation").
///
/// A controller that latches the axis positions once per PLC scan serves them until the next
/// scan: what the daemon reads is up to a scan older than the read. Without a timestamp the loop
/// takes the middle of the read transaction as the sample time. With one (a 16-bit counter of
/// `tickS` seconds, wrapping at 2^16, stamped when the positions were latched):
///
///   unwrap:  the counter's step since the previous sample is taken modulo 2^16 and the wraps
///            added that bring it nearest the daemon's own time between the two replies, so the
///            controller's time c_i (s) runs on without wrapping (right while the two latches'
///            ages differ by less than half a wrap: 2^15 ticks).
///   map:     the positions were latched no later than their reply arrived (r_i, the daemon's
///            clock), so r_i - c_i bounds the clock offset from above; the smallest over the last
///            kClockWindow samples is the sample with the least transport delay, and
///            latched_i = c_i + min_j (r_j - c_j)
///            the daemon-clock time of the latch, to within that least delay. The window keeps the
///            mapping from drifting with the two crystals (100 ppm over 1.3 s at 10 ms: 0.13 ms).
///
/// noexcept and allocation-free (a fixed ring).

#include <chrono>
#include <cstddef>
#include <cstdint>

#include "volcomp/loop/window_minimum.hpp"

namespace volcomp::loop {

inline constexpr std::size_t kClockWindow = 128;

class ControllerClock {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  /// The daemon-clock time at which the controller latched a sample stamped `ticks` (of `tickS`
  /// seconds) whose reply arrived at `replyAt`: never later than `replyAt`, never earlier than
  /// `replyAt - maxAge` (a mapping that puts it there is stale, a controller that restarted its
  /// clock, and starts anew with this sample).
  time_point latchedAt(std::uint16_t ticks, double tickS, time_point replyAt,
                       std::chrono::nanoseconds maxAge) noexcept;

  /// Forget the mapping (a reconnect: the controller may have restarted its clock).
  void reset() noexcept;

  /// Samples the current mapping rests on (0 right after a reset).
  std::size_t samples() const noexcept { return offsets_.size(); }
  /// Samples whose stamp differed from the one before (the first after a reset counts): a
  /// stamp that did not move is the same latch read again.
  std::uint64_t stamps() const noexcept { return stamps_; }

 private:
  time_point map(std::uint16_t ticks, double tickS, time_point replyAt) noexcept;

  WindowMinimum<kClockWindow> offsets_;  ///< r_j - c_j
  bool have_ = false;
  std::uint16_t lastTicks_ = 0;
  double lastTickS_ = 0.0;
  std::int64_t unwrappedTicks_ = 0;  ///< c_i in ticks since the mapping began
  time_point lastReply_{};
  std::uint64_t stamps_ = 0;
};

}  // namespace volcomp::loop
