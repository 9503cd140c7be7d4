#include "volcomp/loop/saturation_monitor.hpp"

#include <cmath>
#include <cstddef>

namespace volcomp::loop {

Saturation SaturationMonitor::update(time_point now, const std::array<double, 3>& targetMm,
                                     const LimiterSettings& limits,
                                     std::chrono::nanoseconds warningAfter,
                                     std::chrono::nanoseconds faultAfter) noexcept {
  Saturation s;
  std::chrono::nanoseconds longest{0};
  for (std::size_t k = 0; k < 3; ++k) {
    const bool clamped = std::abs(targetMm[k]) > limits.axes[k].maxOffsetMm;
    if (clamped && !clamping_[k]) clampSince_[k] = now;
    clamping_[k] = clamped;
    if (clamped && now - clampSince_[k] >= longest) {
      longest = now - clampSince_[k];
      s.axis = static_cast<int>(k);
    }
  }
  if (s.axis >= 0) s.requestedMm = targetMm[static_cast<std::size_t>(s.axis)];
  const auto reached = [&](std::chrono::nanoseconds threshold) {
    return s.axis >= 0 && threshold.count() > 0 && longest >= threshold;
  };
  s.saturated = reached(warningAfter);
  // Once per episode: the daemon logs the start, not every cycle of it.
  s.warningStarted = s.saturated && !warned_;
  warned_ = s.saturated;
  s.fault = reached(faultAfter);
  return s;
}

void SaturationMonitor::reset() noexcept {
  clamping_ = {};
  warned_ = false;
}

}  // namespace volcomp::loop
