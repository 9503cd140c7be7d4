#pragma once
/// The limiter every written offset goes through (daemon.md section 2). Per axis, in this order:
///   target from the model -> clamp to [-maxOffsetMm, +maxOffsetMm]
///   -> slew limit |o_k - o_{k-1}| <= maxRateMmS * dt
///   -> optional acceleration limit |v_k - v_{k-1}| <= maxAccelMmS2 * dt, v_k = (o_k - o_{k-1}) /
///   dt,
///      braking early enough to reach the target without overshoot.
/// Precedence when they conflict: clamp, then rate, then acceleration. An output already outside
/// the clamp band (e.g. a read-back taken over from the controller) moves back into it at the
/// rate limit, never by a jump, and never further out.
/// Pure and noexcept. A NaN or infinite target is never passed through: every axis then ramps
/// towards zero and `invalidTarget` is set, which the loop turns into a fault.

#include <array>

namespace volcomp::loop {

struct LimiterSettings {
  double maxOffsetMm = 0.5;   ///< clamp band, mm (> 0)
  double maxRateMmS = 1.0;    ///< slew limit, mm/s (> 0)
  double maxAccelMmS2 = 0.0;  ///< acceleration limit, mm/s^2; 0 = none
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

}  // namespace volcomp::loop
