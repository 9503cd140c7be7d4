#include "volcomp/linuxcnc/offset_counts.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::linuxcnc {

void OffsetCounts::adopt(std::int32_t signalCounts) noexcept {
  out_ = signalCounts;
  history_.fill(out_);
  rebase_ = true;
}

void OffsetCounts::hold() noexcept {
  // Holding repeats the last value: the history then says LinuxCNC has seen it.
  std::copy_backward(history_.begin(), history_.end() - 1, history_.end());
  history_[0] = out_;
}

std::int32_t OffsetCounts::next(double offsetMm, bool accepting, double requestMm,
                                bool afterSilence) noexcept {
  if (afterSilence) history_.fill(out_);
  if (!accepting || !std::isfinite(requestMm) || !std::isfinite(offsetMm)) {
    rebase_ = rebase_ || !accepting;
    hold();
    return counts();
  }
  const auto requestCounts = static_cast<std::int64_t>(std::llround(requestMm * countsPerMm_));
  if (rebase_) {
    // The counts have not changed since LinuxCNC stopped accepting, so the request has settled.
    base_ = out_ - requestCounts;
    rebase_ = false;
    ++rebases_;
  } else {
    bool consistent = requestCounts == out_ - base_;
    for (std::int64_t earlier : history_)
      consistent = consistent || requestCounts == earlier - base_;
    if (!consistent) {
      // LinuxCNC changed the request on its own (clear, machine-on, a change dropped while it
      // briefly did not accept): hold, so that it settles, and take the base next cycle.
      rebase_ = true;
      hold();
      return counts();
    }
  }
  hold();
  out_ = base_ + static_cast<std::int64_t>(std::llround(offsetMm * countsPerMm_));
  return counts();
}

}  // namespace volcomp::linuxcnc
