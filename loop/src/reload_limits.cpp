#include "volcomp/loop/reload_limits.hpp"

namespace volcomp::loop {

// Every limit an axis has must be merged below: a limit added to AxisLimits and forgotten here
// would be taken from a reload as it is, wider or not.
static_assert(sizeof(AxisLimits) == kLimits.size() * sizeof(double),
              "a new limit in AxisLimits needs its place in Limit and limitValue()");

namespace {

// The field of one limit, const or not as the axis is.
template <typename Axis>
auto& limitField(Axis& axis, Limit limit) noexcept {
  switch (limit) {
    case Limit::MaxOffset:
      return axis.maxOffsetMm;
    case Limit::MaxRate:
      return axis.maxRateMmS;
    case Limit::MaxAccel:
      return axis.maxAccelMmS2;
  }
  return axis.maxOffsetMm;
}

}  // namespace

double limitValue(const AxisLimits& axis, Limit limit) noexcept {
  return limitField(axis, limit);
}

LimitChange compareLimit(Limit limit, double running, double requested) noexcept {
  if (requested == running) return LimitChange::Same;
  // An acceleration limit of 0 is none: any positive limit is stricter, and 0 is the widest.
  const bool stricter = limit == Limit::MaxAccel
                            ? requested > 0.0 && (running == 0.0 || requested < running)
                            : requested < running;
  return stricter ? LimitChange::Tightened : LimitChange::Widened;
}

LimiterSettings stricterLimits(const LimiterSettings& running,
                               const LimiterSettings& requested) noexcept {
  LimiterSettings out = running;
  for (std::size_t k = 0; k < out.axes.size(); ++k) {
    for (const Limit limit : kLimits) {
      const double wanted = limitValue(requested.axes[k], limit);
      double& value = limitField(out.axes[k], limit);
      if (compareLimit(limit, value, wanted) == LimitChange::Tightened) value = wanted;
    }
  }
  return out;
}

}  // namespace volcomp::loop
