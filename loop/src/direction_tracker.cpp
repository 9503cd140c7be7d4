#include "volcomp/loop/direction_tracker.hpp"

namespace volcomp::loop {

const model::Directions& DirectionTracker::update(
    const std::array<double, 3>& positionMm) noexcept {
  if (!initialised_) {
    referenceMm_ = positionMm;
    initialised_ = true;
    return directions_;
  }
  for (int k = 0; k < 3; ++k) {
    const double q = positionMm[k];
    double& r = referenceMm_[k];
    model::Direction& d = directions_[k];
    switch (d) {
      case model::Direction::Positive:
        if (q > r)
          r = q;
        else if (q < r - hysteresisMm_) {
          d = model::Direction::Negative;
          r = q;
        }
        break;
      case model::Direction::Negative:
        if (q < r)
          r = q;
        else if (q > r + hysteresisMm_) {
          d = model::Direction::Positive;
          r = q;
        }
        break;
      case model::Direction::Unknown:
        if (q > r + hysteresisMm_) {
          d = model::Direction::Positive;
          r = q;
        } else if (q < r - hysteresisMm_) {
          d = model::Direction::Negative;
          r = q;
        }
        break;
    }
  }
  return directions_;
}

void DirectionTracker::reset() noexcept {
  initialised_ = false;
  directions_ = {model::Direction::Unknown, model::Direction::Unknown, model::Direction::Unknown};
}

}  // namespace volcomp::loop
