#pragma once
/// Sustained limiting (docs/daemon.md, `limiter.saturation_warning_ms` and
/// `limiter.saturation_fault_ms`): the clamp, not the slew, holding an axis, i.e. the model asking
/// for more offset than the installation allows. Per axis k (machine axes X, Y, Z), with t_k the
/// model's target offset (mm) of a cycle in which the model was evaluated:
///
///   clamped_k  |t_k| > maxOffsetMm_k: the target is outside the clamp band (slewing towards a
///              target inside the band is not saturation);
///   held_k     now - the first cycle of the current run of clamped cycles of axis k; a cycle in
///              which it is not clamped, or reset() (a cycle without a model evaluation), ends it;
///   longest    the clamped axis with the largest held_k (the higher axis on a tie);
///   saturated  held_longest >= warningAfter: the SATURATED bit. The warning starts in the first
///              saturated cycle after one that was not, naming that axis and its target;
///   fault      held_longest >= faultAfter: the fault SustainedLimit.
/// A threshold of zero disables its stage. Times are the loop's clock. noexcept.

#include <array>
#include <chrono>

#include "volcomp/loop/limiter.hpp"

namespace volcomp::loop {

/// What one evaluated cycle's targets mean for sustained limiting.
struct Saturation {
  /// The clamped axis held longest (0..2), -1 when no axis is clamped.
  int axis = -1;
  /// The target on that axis (mm): what the model asked for.
  double requestedMm = 0.0;
  /// The warning threshold is reached (status bit SATURATED).
  bool saturated = false;
  /// ... in this cycle and not in the one before: the warning starts.
  bool warningStarted = false;
  /// The fault threshold is reached (fault SustainedLimit).
  bool fault = false;
};

class SaturationMonitor {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  /// The targets `targetMm` (mm) of a cycle at `now` in which the model was evaluated.
  Saturation update(time_point now, const std::array<double, 3>& targetMm,
                    const LimiterSettings& limits, std::chrono::nanoseconds warningAfter,
                    std::chrono::nanoseconds faultAfter) noexcept;
  /// A cycle without a model evaluation: every run of clamped cycles ends, the warning too.
  void reset() noexcept;

 private:
  std::array<bool, 3> clamping_{};
  std::array<time_point, 3> clampSince_{};
  bool warned_ = false;
};

}  // namespace volcomp::loop
