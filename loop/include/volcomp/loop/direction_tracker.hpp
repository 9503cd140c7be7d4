#pragma once
/// Direction in which each axis last moved, with hysteresis (docs/model-file.md "Error functions":
/// bidirectional tables): selects the curve of bidirectional tables. Per axis the tracker keeps a
/// reference position r:
///   - while the direction is Positive, r follows the highest position seen; the direction turns
///     Negative once q < r - h (and symmetrically for Negative);
///   - while Unknown (at start), it becomes Positive when q > r + h and Negative when q < r - h.
/// So noise smaller than the hysteresis h (mm) never toggles the direction. Pure and noexcept.

#include <array>

#include "volcomp/model/types.hpp"

namespace volcomp::loop {

class DirectionTracker {
 public:
  explicit DirectionTracker(double hysteresisMm = 0.002) noexcept : hysteresisMm_(hysteresisMm) {}

  /// Feeds the positions (mm) of one cycle and returns the directions.
  const model::Directions& update(const std::array<double, 3>& positionMm) noexcept;
  /// Forgets everything (directions Unknown); the next update sets the references.
  void reset() noexcept;
  void setHysteresis(double hysteresisMm) noexcept { hysteresisMm_ = hysteresisMm; }
  const model::Directions& directions() const noexcept { return directions_; }

 private:
  double hysteresisMm_;
  bool initialised_ = false;
  std::array<double, 3> referenceMm_{};
  model::Directions directions_{model::Direction::Unknown, model::Direction::Unknown,
                                model::Direction::Unknown};
};

}  // namespace volcomp::loop
