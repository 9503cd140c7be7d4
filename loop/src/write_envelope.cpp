#include "volcomp/loop/write_envelope.hpp"

#include <algorithm>
#include <cstddef>

namespace volcomp::loop {

void WriteEnvelope::widen(const std::array<double, 3>& fromMm,
                          const std::array<double, 3>& attemptedMm) noexcept {
  for (std::size_t k = 0; k < 3; ++k) {
    // The first unknown outcome starts the hull at the value stepped from; later ones can only
    // add to it, since any earlier attempt may still be what the controller applies.
    const double lo = uncertain_ ? lowMm_[k] : fromMm[k];
    const double hi = uncertain_ ? highMm_[k] : fromMm[k];
    lowMm_[k] = std::min(lo, attemptedMm[k]);
    highMm_[k] = std::max(hi, attemptedMm[k]);
  }
  uncertain_ = true;
}

bool WriteEnvelope::constrain(const LimiterSettings& limits, const LimiterState& before, double dtS,
                              LimiterState& state) const noexcept {
  if (!uncertain_) return true;
  LimiterState constrained = state;
  for (std::size_t k = 0; k < 3; ++k) {
    const double stepMm = limits.axes[k].maxRateMmS * dtS;
    const double lo = highMm_[k] - stepMm;
    const double hi = lowMm_[k] + stepMm;
    // Rounding of the bounds' arithmetic must not withhold a write whose window is a point.
    if (lo > hi + 1e-12) return false;
    constrained.offsetMm[k] = std::clamp(state.offsetMm[k], lo, std::max(lo, hi));
    constrained.velocityMmS[k] =
        dtS > 0.0 ? (constrained.offsetMm[k] - before.offsetMm[k]) / dtS : 0.0;
  }
  state = constrained;
  return true;
}

}  // namespace volcomp::loop
