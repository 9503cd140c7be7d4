#pragma once
/// Latency compensation: the positions a cycle reads are old when its offset acts, so the model is
/// evaluated where each axis will be then, q + v h, instead of where it was read (docs/daemon.md
/// "Latency compensation").
///
/// VelocityEstimator keeps the last kVelocitySamples positions (mm, machine axes) with the times
/// the controller sampled them (the loop's clock, mid-read). Per axis:
///   v_fit  = least-squares slope of q over t (the times are measured, so read jitter shifts a
///            sample in time, not the slope; the fit averages what is left),
///   v_last = the slope of the newest pair,
///   v      = the one of smaller magnitude, and only when every step in the window, v_fit and
///            v_last have the same sign: the axis moved monotonically over the window.
/// Otherwise the estimate is unsure (a reversal, a stop, too few samples) and the axis is evaluated
/// at its measured position, so that no extrapolation ever runs across a turning point. A sample
/// more than `maxGap` after the previous one starts a new window (stale history).
///
/// predictPositions(): q_eval = q + v h per axis with the horizon h capped at `maxHorizon`; unsure
/// axes keep q. Everything is noexcept and allocation-free (fixed arrays).

#include <array>
#include <chrono>
#include <cstddef>

#include "volcomp/model/types.hpp"

namespace volcomp::loop {

inline constexpr std::size_t kVelocitySamples = 4;

/// The velocity of one axis, when the window says it reliably.
struct AxisVelocity {
  bool sure = false;
  double mmS = 0.0;
};

class VelocityEstimator {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  /// Forgets every sample (start, reconnect, a pause of the evaluation).
  void reset() noexcept { count_ = 0; }
  /// Adds positions sampled at t. A sample not later than the newest replaces it; one more than
  /// maxGap after it starts a new window.
  void add(time_point t, const std::array<double, 3>& qMm,
           std::chrono::nanoseconds maxGap) noexcept;
  std::size_t size() const noexcept { return count_; }
  /// Time of the newest sample (meaningless while size() == 0).
  time_point newest() const noexcept { return t_[index(count_ - 1)]; }
  /// The estimate of axis k (0..2); unsure with fewer than three samples.
  AxisVelocity velocity(std::size_t k) const noexcept;
  /// How far axis k moved over the window (newest - oldest, mm; 0 with fewer than two samples).
  double spanMm(std::size_t k) const noexcept {
    return count_ < 2 ? 0.0 : q_[index(count_ - 1)][k] - q_[index(0)][k];
  }

 private:
  std::size_t index(std::size_t i) const noexcept { return (first_ + i) % kVelocitySamples; }

  std::array<time_point, kVelocitySamples> t_{};
  std::array<std::array<double, 3>, kVelocitySamples> q_{};
  std::size_t first_ = 0;
  std::size_t count_ = 0;
};

/// Where to evaluate the model: q + v h per sure axis that moved more than `minSpanMm` over the
/// window (the direction tracker's hysteresis: noise at rest is never extrapolated and never sets
/// a direction), h = min(horizon, maxHorizon); q elsewhere. `directions` gets the sign of v on
/// the axes extrapolated and keeps the tracker's elsewhere. Returns the number of axes
/// extrapolated.
int predictPositions(const VelocityEstimator& estimator, std::array<double, 3>& qMm,
                     model::Directions& directions, std::chrono::nanoseconds horizon,
                     std::chrono::nanoseconds maxHorizon, double minSpanMm) noexcept;

}  // namespace volcomp::loop
