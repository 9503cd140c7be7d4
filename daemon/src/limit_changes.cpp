#include "volcomp/daemon/limit_changes.hpp"

#include <fmt/format.h>

#include <array>
#include <cstddef>

#include "volcomp/loop/reload_limits.hpp"

namespace volcomp::daemon {
namespace {

using loop::Limit;
using loop::LimitChange;

struct LimitName {
  const char* key;
  const char* unit;
};

LimitName nameOf(Limit limit) {
  switch (limit) {
    case Limit::MaxOffset:
      return {"max_offset_mm", "mm"};
    case Limit::MaxRate:
      return {"max_rate_mm_s", "mm/s"};
    case Limit::MaxAccel:
      return {"max_accel_mm_s2", "mm/s^2"};
  }
  return {"?", ""};
}

// An acceleration limit of 0 is written as the configuration means it.
std::string valueText(Limit limit, double value) {
  if (limit == Limit::MaxAccel && value == 0.0) return "none";
  return fmt::format("{:g}", value);
}

// "X/Y/Z 0.1 -> 2 mm" or "X 0.1 -> 2 mm, Z 0.05 -> 2 mm": the axes of one kind of change, those
// with the same old and new values in one entry, so that a uniform limiter makes a short line.
std::string axesText(Limit limit, LimitChange kind, const loop::LimiterSettings& running,
                     const loop::LimiterSettings& requested) {
  std::array<bool, 3> done{};
  std::string text;
  for (std::size_t k = 0; k < 3; ++k) {
    const double from = loop::limitValue(running.axes[k], limit);
    const double to = loop::limitValue(requested.axes[k], limit);
    if (done[k] || loop::compareLimit(limit, from, to) != kind) continue;
    std::string axes(1, "XYZ"[k]);
    for (std::size_t j = k + 1; j < 3; ++j) {
      if (loop::limitValue(running.axes[j], limit) == from &&
          loop::limitValue(requested.axes[j], limit) == to) {
        axes += std::string("/") + "XYZ"[j];
        done[j] = true;
      }
    }
    const char* unit = nameOf(limit).unit;
    // The unit goes with the number: "20 mm/s^2 -> none", "none -> 20 mm/s^2", "0.1 -> 2 mm".
    const std::string change =
        limit == Limit::MaxAccel && to == 0.0
            ? fmt::format("{} {} -> none", valueText(limit, from), unit)
            : fmt::format("{} -> {} {}", valueText(limit, from), valueText(limit, to), unit);
    text += fmt::format("{}{} {}", text.empty() ? "" : ", ", axes, change);
  }
  return text;
}

}  // namespace

LimitChangeLines describeLimitChanges(const loop::LimiterSettings& running,
                                      const loop::LimiterSettings& requested,
                                      const std::string& file) {
  LimitChangeLines lines;
  for (const Limit limit : loop::kLimits) {
    const char* key = nameOf(limit).key;
    if (std::string t = axesText(limit, LimitChange::Tightened, running, requested); !t.empty()) {
      lines.tightened.push_back(
          fmt::format("limiter.{} tightened by the reload: {}, taken now", key, t));
    }
    if (std::string w = axesText(limit, LimitChange::Widened, running, requested); !w.empty()) {
      lines.widened.push_back(fmt::format(
          "limiter.{} of {} widens {}: not taken while compensating, the running limit stays; "
          "a wider limit takes effect on restart (systemctl restart volcompd)",
          key, file, w));
    }
  }
  return lines;
}

}  // namespace volcomp::daemon
