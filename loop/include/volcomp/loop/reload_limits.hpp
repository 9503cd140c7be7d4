#pragma once
/// What new settings may do to the limits of a running loop (docs/daemon.md "Reload"): they only
/// tighten. Per axis and limit (max offset mm, max rate mm/s, max acceleration mm/s^2) the loop
/// keeps the stricter of its running value and the requested one; a wider value takes effect
/// only in a new loop, i.e. when the daemon restarts. "Stricter" is the smaller value, except that
/// an acceleration limit of 0 means none, the widest of all: any positive one is stricter.
/// A requested value that is not a number is never stricter. Pure and noexcept.

#include <array>
#include <cstdint>

#include "volcomp/loop/limiter.hpp"

namespace volcomp::loop {

/// One limit of an axis (a field of AxisLimits).
enum class Limit : std::uint8_t { MaxOffset, MaxRate, MaxAccel };

inline constexpr std::array<Limit, 3> kLimits{Limit::MaxOffset, Limit::MaxRate, Limit::MaxAccel};

/// How a requested value of a limit compares with the running one.
enum class LimitChange : std::uint8_t { Same, Tightened, Widened };

/// The value of `limit` of one axis: mm, mm/s or mm/s^2 (MaxAccel 0 = none).
double limitValue(const AxisLimits& axis, Limit limit) noexcept;

/// Same, Tightened (requested is stricter than running) or Widened (anything else).
LimitChange compareLimit(Limit limit, double running, double requested) noexcept;

/// Per axis and limit the stricter of `running` and `requested`: the limits a running loop takes
/// from new settings.
LimiterSettings stricterLimits(const LimiterSettings& running,
                               const LimiterSettings& requested) noexcept;

}  // namespace volcomp::loop
