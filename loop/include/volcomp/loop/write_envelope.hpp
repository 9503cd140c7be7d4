#pragma once
/// What the controller may be applying after writes whose outcome is unknown (docs/daemon.md
/// "Timing faults"). A write that timed out or got a mismatched reply may have been applied or
/// not: until a write is acknowledged the controller applies the value the limiter stepped from
/// (the last acknowledged one) or any value attempted since. Per axis k, offsets in mm on the
/// machine axes X, Y, Z as written to the controller:
///
///   envelope   [lowMm_k, highMm_k], the hull of the value stepped from and every value attempted
///              since it was acknowledged;
///   window     the next output o_k must be within one limiter step s_k = maxRateMmS_k * dtS of
///              every value in the envelope: highMm_k - s_k <= o_k <= lowMm_k + s_k. The limiter
///              steps from the last value attempted, which is inside the envelope, so the window
///              is empty only when dt shrank below half the step that made the envelope: then
///              nothing may be written that cycle;
///   clear      an acknowledged write, or offsets read back and adopted, makes the applied value
///              known again: no envelope, no window.
/// noexcept and allocation-free.

#include <array>

#include "volcomp/loop/limiter.hpp"

namespace volcomp::loop {

class WriteEnvelope {
 public:
  /// A write whose outcome is unknown: `fromMm` is the value the limiter stepped from (the last
  /// acknowledged one when nothing was uncertain before), `attemptedMm` the value it carried.
  void widen(const std::array<double, 3>& fromMm,
             const std::array<double, 3>& attemptedMm) noexcept;
  /// The applied offsets are known again.
  void clear() noexcept { uncertain_ = false; }

  /// Moves `state` (the limiter's output after a step of `dtS` seconds from `before`) into the
  /// window of every axis, its velocity (mm/s) following. Returns false, `state` untouched, when
  /// the window of an axis is empty; true, `state` untouched, when nothing is uncertain.
  bool constrain(const LimiterSettings& limits, const LimiterState& before, double dtS,
                 LimiterState& state) const noexcept;

  /// True after a write with an unknown outcome, until clear().
  bool uncertain() const noexcept { return uncertain_; }
  const std::array<double, 3>& lowMm() const noexcept { return lowMm_; }
  const std::array<double, 3>& highMm() const noexcept { return highMm_; }

 private:
  bool uncertain_ = false;
  std::array<double, 3> lowMm_{};
  std::array<double, 3> highMm_{};
};

}  // namespace volcomp::loop
