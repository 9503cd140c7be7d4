#pragma once
/// What a reload does to the running limiter, as log lines. While compensating the limits only
/// tighten (loop/reload_limits.hpp): per limit of the configuration's "limiter"
/// (max_offset_mm in mm, max_rate_mm_s in mm/s, max_accel_mm_s2 in mm/s^2, 0 = none) one line for
/// the axes whose new value is stricter, taken at once, and one for the axes whose new value is
/// wider, not taken: the running value stays until a restart. Each names the axes with
/// old -> new; axes with the same change share one entry ("X/Y/Z 0.1 -> 2 mm").

#include <string>
#include <vector>

#include "volcomp/loop/limiter.hpp"

namespace volcomp::daemon {

struct LimitChangeLines {
  std::vector<std::string> tightened;  ///< logged as information
  std::vector<std::string> widened;    ///< logged as warnings, with what to do
};

/// `running`: the limits the loop runs with; `requested`: those of the reloaded `file`.
LimitChangeLines describeLimitChanges(const loop::LimiterSettings& running,
                                      const loop::LimiterSettings& requested,
                                      const std::string& file);

}  // namespace volcomp::daemon
