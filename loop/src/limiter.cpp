#include "volcomp/loop/limiter.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::loop {
namespace {

struct AxisResult {
  double offset;
  double velocity;
};

AxisResult limitAxis(const AxisLimits& s, double previous, double previousVelocity, double target,
                     double dt) noexcept {
  const double band = s.maxOffsetMm;
  const double clamped = std::clamp(target, -band, band);
  const double error = clamped - previous;
  const double maxStep = s.maxRateMmS * dt;
  double step = std::clamp(error, -maxStep, maxStep);

  if (s.maxAccelMmS2 > 0.0) {
    const double a = s.maxAccelMmS2;
    // Largest speed from which braking at `a` (one velocity change a*dt per cycle) still stops
    // within |error|: v^2/(2a) + v*dt/2 <= |error|, solved for v. Without it the acceleration
    // limit alone would overshoot the target.
    const double brakeSpeed =
        a * (-0.5 * dt + std::sqrt(0.25 * dt * dt + 2.0 * std::abs(error) / a));
    double desired = step / dt;
    desired = std::clamp(desired, -brakeSpeed, brakeSpeed);
    const double velocity =
        std::clamp(desired, previousVelocity - a * dt, previousVelocity + a * dt);
    step = std::clamp(velocity * dt, -maxStep, maxStep);
  }

  double out = previous + step;
  // Never further out of the band than where we were (the clamp wins over acceleration).
  if (out > band) out = std::max(band, std::min(out, previous));
  if (out < -band) out = std::min(-band, std::max(out, previous));
  // Land exactly on the target when it is within reach, so that "at zero" means exactly zero.
  if (std::abs(clamped - out) <= 1e-12) out = clamped;
  return {out, (out - previous) / dt};
}

}  // namespace

LimiterOutput limitStep(const LimiterSettings& settings, LimiterState& state,
                        const std::array<double, 3>& targetMm, double dtS) noexcept {
  LimiterOutput result;
  bool finite = true;
  for (double t : targetMm) finite = finite && std::isfinite(t);
  result.invalidTarget = !finite;

  if (!(dtS > 0.0) || !std::isfinite(dtS)) {
    result.offsetMm = state.offsetMm;
    for (int k = 0; k < 3; ++k) result.limited = result.limited || state.offsetMm[k] != targetMm[k];
    return result;
  }
  for (int k = 0; k < 3; ++k) {
    const AxisLimits& limits = settings.axes[static_cast<std::size_t>(k)];
    const double target = finite ? targetMm[k] : 0.0;
    if (std::abs(target) > limits.maxOffsetMm) {
      result.clampedAxes = static_cast<std::uint8_t>(result.clampedAxes | (1u << k));
    }
    const AxisResult axis = limitAxis(limits, state.offsetMm[k], state.velocityMmS[k], target, dtS);
    state.offsetMm[k] = axis.offset;
    state.velocityMmS[k] = axis.velocity;
    result.offsetMm[k] = axis.offset;
    result.limited = result.limited || axis.offset != target;
  }
  return result;
}

void resetLimiter(LimiterState& state, const std::array<double, 3>& appliedMm) noexcept {
  for (int k = 0; k < 3; ++k) {
    state.offsetMm[k] = std::isfinite(appliedMm[k]) ? appliedMm[k] : 0.0;
    state.velocityMmS[k] = 0.0;
  }
}

bool limiterAtZero(const LimiterState& state) noexcept {
  for (int k = 0; k < 3; ++k) {
    if (state.offsetMm[k] != 0.0) return false;
  }
  return true;
}

bool withinBand(const LimiterSettings& settings, const std::array<double, 3>& valueMm,
                double toleranceMm) noexcept {
  for (std::size_t k = 0; k < 3; ++k) {
    if (!(std::abs(valueMm[k]) <= settings.axes[k].maxOffsetMm + toleranceMm)) return false;
  }
  return true;
}

double rampOutSeconds(const LimiterSettings& settings,
                      const std::array<double, 3>& offsetMm) noexcept {
  double longest = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const AxisLimits& a = settings.axes[k];
    double s = std::abs(offsetMm[k]) / a.maxRateMmS;
    if (a.maxAccelMmS2 > 0.0) s += 2.0 * a.maxRateMmS / a.maxAccelMmS2;
    if (std::isfinite(s)) longest = std::max(longest, s);
  }
  return longest;
}

}  // namespace volcomp::loop
