#include "volcomp/daemon/loop_settings.hpp"

#include <cmath>

namespace volcomp::daemon {
namespace {

std::chrono::nanoseconds fromMs(double ms) noexcept {
  return std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(ms * 1e6)));
}

}  // namespace

LoopSettings loopSettingsFrom(const config::DaemonConfig& c) noexcept {
  LoopSettings s;
  s.period = fromMs(c.cyclePeriodMs);
  s.semantics = c.positionSemantics;
  s.limiter.maxOffsetMm = c.limiter.maxOffsetMm;
  s.limiter.maxRateMmS = c.limiter.maxRateMmS;
  s.limiter.maxAccelMmS2 = c.limiter.maxAccelMmS2;
  s.staleTimeout = fromMs(c.staleTimeoutMs);
  s.frozenPositionsAreStale = c.frozenPositionsAreStale;
  s.travelMarginMm = c.travelMarginMm;
  s.directionHysteresisMm = c.directionHysteresisMm;
  s.offsetReadback = c.offsetReadback;
  s.plcZeroAfter = fromMs(c.plcZeroAfterMs.value_or(0.0));
  s.reconnectInitial = fromMs(c.reconnect.initialMs);
  s.reconnectMax = fromMs(c.reconnect.maxMs);
  return s;
}

}  // namespace volcomp::daemon
