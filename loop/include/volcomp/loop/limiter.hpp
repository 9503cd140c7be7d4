#pragma once
/// The limiter every written offset goes through (docs/daemon.md "What each cycle does"). Per axis
/// k, with the limits of that axis, in this order:
///   target from the model -> clamp to [-maxOffsetMm_k, +maxOffsetMm_k]
///   -> slew limit |o_i - o_{i-1}| <= maxRateMmS_k * dt
///   -> optional acceleration limit |v_i - v_{i-1}| <= maxAccelMmS2_k * dt, v_i = (o_i - o_{i-1})
///      / dt, braking early enough to reach the target without overshoot.
/// dt is the time since the previous output was sent (the loop measures it and caps it at one
/// nominal period), so late cycles cannot bunch steps: over any window the offset moves by at
/// most max_rate times the window.
/// Precedence when they conflict: clamp, then rate, then acceleration. An output already outside
/// the clamp band (e.g. a read-back taken over from the controller) moves back into it at the
/// rate limit, never by a jump, and never further out.
/// Pure and noexcept. A NaN or infinite target is never passed through: every axis then ramps
/// towards zero and `invalidTarget` is set, which the loop turns into a fault.

#include <array>
#include <cstdint>

namespace volcomp::loop {

/// The limits of one axis.
struct AxisLimits {
  double maxOffsetMm = 0.5;   ///< clamp band, mm (> 0)
  double maxRateMmS = 1.0;    ///< slew limit, mm/s (> 0)
  double maxAccelMmS2 = 0.0;  ///< acceleration limit, mm/s^2; 0 = none
  bool operator==(const AxisLimits&) const = default;
};

struct LimiterSettings {
  std::array<AxisLimits, 3> axes{};  ///< X, Y, Z
  /// The same limits on every axis.
  static LimiterSettings uniform(double maxOffsetMm, double maxRateMmS,
                                 double maxAccelMmS2 = 0.0) noexcept {
    LimiterSettings s;
    for (AxisLimits& a : s.axes) a = {maxOffsetMm, maxRateMmS, maxAccelMmS2};
    return s;
  }
  bool operator==(const LimiterSettings&) const = default;
};

/// What the limiter remembers between cycles: the last output and its velocity, per axis.
struct LimiterState {
  std::array<double, 3> offsetMm{};
  std::array<double, 3> velocityMmS{};
};

struct LimiterOutput {
  std::array<double, 3> offsetMm{};
  /// True when the output differs from the target on at least one axis (clamped or rate-limited).
  bool limited = false;
  /// Bit k: the target of axis k was outside its clamp band (the clamp, not the slew, acted).
  std::uint8_t clampedAxes = 0;
  /// True when a target was NaN or infinite (the output then ramps towards zero).
  bool invalidTarget = false;
};

/// One limiter step of length dtS seconds: updates `state` and returns the output (= state).
/// A non-positive or non-finite dtS leaves the output where it was.
LimiterOutput limitStep(const LimiterSettings& settings, LimiterState& state,
                        const std::array<double, 3>& targetMm, double dtS) noexcept;

/// Restarts the limiter from offsets known to be applied (read back, or zero), at rest.
/// Non-finite values are taken as 0.
void resetLimiter(LimiterState& state, const std::array<double, 3>& appliedMm) noexcept;

/// True when the output of every axis is exactly zero.
bool limiterAtZero(const LimiterState& state) noexcept;

/// True when |valueMm_k| <= maxOffsetMm_k + toleranceMm on every axis (NaN is outside).
bool withinBand(const LimiterSettings& settings, const std::array<double, 3>& valueMm,
                double toleranceMm) noexcept;

/// Longest time (s) the limiter needs to bring `offsetMm` to zero from rest: per axis
/// |o_k| / maxRate_k, plus the time to accelerate to and brake from max_rate when an
/// acceleration limit is set.
double rampOutSeconds(const LimiterSettings& settings,
                      const std::array<double, 3>& offsetMm) noexcept;

}  // namespace volcomp::loop
