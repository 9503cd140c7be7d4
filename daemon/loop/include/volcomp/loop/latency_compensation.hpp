#pragma once
/// Latency compensation: the positions a cycle reads are old by the time its offset acts, so the
/// model is evaluated where each axis will be then, q(t_act) ~ q + v * h, not where it was read.
///
/// Velocity, per axis, from timestamped positions (mm, s), robust to timing jitter and to
/// reversals: the least-squares slope of the last three samples (the timestamps are the loop's
/// read times, which jitter by the scheduling noise; the fit halves its effect on v), except when
/// the last two differences point in opposite directions (a reversal between them), where the
/// last difference alone is used, so that the estimate turns with the axis instead of averaging
/// the two directions. Samples whose positions did not change because the controller did not
/// refresh its registers (life counter unchanged) are not added.
///
/// Horizon h = (write time - read start) + controllerLatency + period / 2: the read and the write
/// transactions take about equally long, so the write lands about one read-to-write time after
/// the controller sampled the positions; the controller needs its own latency to apply it; and the
/// offset then stays for one period, whose middle is the point that minimises the error over it.
/// Pure and noexcept.

#include <array>
#include <cstdint>

namespace volcomp::loop {

class VelocityEstimator {
 public:
  /// Forgets every sample (after a reconnect, a stale period, a reload of the settings).
  void reset() noexcept { count_ = 0; }
  /// Adds the positions read at tS (any monotonic seconds). A sample not later than the previous
  /// one replaces it.
  void add(double tS, const std::array<double, 3>& qMm) noexcept;
  /// True once two samples give a velocity.
  bool valid() const noexcept { return count_ >= 2; }
  /// Velocity per axis, mm/s (zero until valid()).
  std::array<double, 3> velocityMmS() const noexcept;

 private:
  double origin_ = 0.0;  // the first sample's time: the fit works on small times, not on epochs
  std::array<double, 3> t_{};                 // oldest first, relative to origin_
  std::array<std::array<double, 3>, 3> q_{};  // q_[i][axis]
  int count_ = 0;
};

/// q + v * h per axis, each axis kept inside its travel [lo, hi] when the measured position is
/// inside it (an extrapolation must not invent an out-of-travel position).
std::array<double, 3> extrapolate(const std::array<double, 3>& qMm,
                                  const std::array<double, 3>& velocityMmS, double horizonS,
                                  const std::array<double, 3>& travelLoMm,
                                  const std::array<double, 3>& travelHiMm) noexcept;

}  // namespace volcomp::loop
