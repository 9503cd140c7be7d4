#pragma once
/// Latency compensation: the positions a cycle reads are old when its offset acts, so the model is
/// evaluated where each axis will be then, q + v h, instead of where it was read (docs/daemon.md
/// "Latency compensation").
///
/// VelocityEstimator keeps the last kHistorySamples positions (mm, machine axes) with the times
/// the controller sampled them (the loop's clock, mid-read). Per axis, over the newest
/// kVelocitySamples of them:
///   v_fit  = least-squares slope of q over t (the times are measured, so read jitter shifts a
///            sample in time, not the slope; the fit averages what is left),
///   v_last = the slope of the newest pair,
///   v      = the one of smaller magnitude, and only when every step in the window, v_fit and
///            v_last have the same sign: the axis moved monotonically over the window.
/// Otherwise the estimate is unsure (a reversal, a stop, too few samples) and the axis is evaluated
/// at its measured position, so that no linear extrapolation runs across a turning point. A sample
/// more than `maxGap` after the previous one starts a new window (stale history).
///
/// predictPositions(): q_eval = q + v h per axis with the horizon h capped at `maxHorizon`; unsure
/// axes keep q.
///
/// Smooth turns (a circle's quadrant change, a reversal braked at constant deceleration): the
/// linear estimate cannot see them coming, and a bidirectional table then stays on the old curve
/// until the daemon has read the turn and written again. parabola() fits q(t) = c0 + c1 t + c2 t^2
/// (t relative to the newest sample) over the last kHistorySamples reads; where that fit is
/// smooth (RMS residual below 2 % of the axis's travel over the window: a velocity jump, an
/// unbraked reversal, is not) predictHold() finds the turn t* = -c1 / (2 c2) and, when it falls
/// in the hold the offset is about to act for, the fraction of the hold before it. The loop then
/// writes the hold's mean of the two curves' offsets, the constant closest (least squares) to the
/// ideal offset that jumps at the turn.
///
/// Everything is noexcept and allocation-free (fixed arrays).

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>

#include "volcomp/model/types.hpp"

namespace volcomp::loop {

inline constexpr std::size_t kVelocitySamples = 4;
/// Reads kept for the parabola (the newest kVelocitySamples of them give the velocity).
inline constexpr std::size_t kHistorySamples = 6;

/// The velocity of one axis, when the window says it reliably.
struct AxisVelocity {
  bool sure = false;
  double mmS = 0.0;
};

/// q(t) = c0 + c1 t + c2 t^2 (mm, t in s relative to the newest sample) fitted to the window.
struct AxisParabola {
  bool smooth = false;  ///< at least 5 samples, RMS residual <= max(2 % of rangeMm, floor)
  double c0 = 0.0, c1 = 0.0, c2 = 0.0;
  double rangeMm = 0.0;  ///< max - min of the samples fitted
  double oldestS = 0.0;  ///< time of the oldest sample (negative)
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
  /// The estimate of axis k (0..2) from the newest kVelocitySamples; unsure with fewer than three.
  AxisVelocity velocity(std::size_t k) const noexcept;
  /// How far axis k moved over the velocity window (newest - oldest of the newest
  /// kVelocitySamples, mm; 0 with fewer than two samples).
  double spanMm(std::size_t k) const noexcept {
    const std::size_t n = std::min(count_, kVelocitySamples);
    return n < 2 ? 0.0 : q_[index(count_ - 1)][k] - q_[index(count_ - n)][k];
  }
  /// The parabola of axis k through the oldest `samples` kept samples (all by default), times
  /// relative to the newest sample; a residual above max(2 % of their range, floorMm) is not
  /// smooth.
  AxisParabola parabola(std::size_t k, double floorMm,
                        std::size_t samples = kHistorySamples) const noexcept;
  /// Time of kept sample i (0 = oldest) relative to the newest, s (<= 0).
  double sinceNewestS(std::size_t i) const noexcept;

 private:
  std::size_t index(std::size_t i) const noexcept { return (first_ + i) % kHistorySamples; }

  std::array<time_point, kHistorySamples> t_{};
  std::array<std::array<double, 3>, kHistorySamples> q_{};
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

/// The hold an offset is about to act for: from horizon - period/2 to horizon + period/2 after
/// the newest sample. What predictHold() says about it.
struct HoldPrediction {
  std::array<double, 3> qMm{};     ///< positions at the middle of the hold, mm
  model::Directions directions{};  ///< directions at its start
  int extrapolated = 0;            ///< axes moved from their read position
  std::size_t turns = 0;           ///< axes turning within the hold (at most 3)
  std::array<std::size_t, 3> turnAxis{};
  std::array<double, 3> turnFraction{};  ///< fraction of the hold before each turn, ascending
};

/// predictPositions() for the middle of the hold, refined by the parabola on axes whose window is
/// smooth and moved more than 10 x minSpanMm: an axis braking towards a turn before the hold's
/// end is placed on the parabola and either takes the new direction (turn before the hold) or is
/// listed with the fraction of the hold before its turn; an axis whose turn fell between the two
/// newest reads (the tracker cannot have seen it yet) takes the new direction unless the newest
/// read went on beyond the vertex of the parabola of the reads before it by more than half of
/// minSpanMm (a stop and on in the same direction). Unchanged on the other axes: `tracked`
/// directions, read positions.
///
/// A stop is a turn to this rule until the next read: braking to a stop looks the same as braking
/// into a reversal, so the hold in which an axis stops is taken as turning there.
HoldPrediction predictHold(const VelocityEstimator& estimator, const std::array<double, 3>& qMm,
                           const model::Directions& tracked, std::chrono::nanoseconds horizon,
                           std::chrono::nanoseconds period, std::chrono::nanoseconds maxHorizon,
                           double minSpanMm) noexcept;

}  // namespace volcomp::loop
