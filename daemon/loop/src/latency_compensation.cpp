#include "volcomp/loop/latency_compensation.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::loop {

void VelocityEstimator::add(double absoluteS, const std::array<double, 3>& qMm) noexcept {
  if (count_ == 0) origin_ = absoluteS;
  const double tS = absoluteS - origin_;
  if (count_ > 0 && !(tS > t_[static_cast<std::size_t>(std::min(count_, 3) - 1)])) {
    const auto last = static_cast<std::size_t>(std::min(count_, 3) - 1);
    t_[last] = tS;
    q_[last] = qMm;
    return;
  }
  if (count_ >= 3) {
    t_[0] = t_[1];
    t_[1] = t_[2];
    q_[0] = q_[1];
    q_[1] = q_[2];
    t_[2] = tS;
    q_[2] = qMm;
  } else {
    t_[static_cast<std::size_t>(count_)] = tS;
    q_[static_cast<std::size_t>(count_)] = qMm;
    ++count_;
  }
}

std::array<double, 3> VelocityEstimator::velocityMmS() const noexcept {
  std::array<double, 3> v{};
  if (count_ < 2) return v;
  const std::size_t n = static_cast<std::size_t>(count_);
  const std::size_t last = n - 1;
  for (std::size_t k = 0; k < 3; ++k) {
    const double lastDifference = q_[last][k] - q_[last - 1][k];
    const double lastSlope = lastDifference / (t_[last] - t_[last - 1]);
    if (n == 2) {
      v[k] = lastSlope;
      continue;
    }
    const double previousDifference = q_[1][k] - q_[0][k];
    if (lastDifference * previousDifference < 0.0) {
      v[k] = lastSlope;  // reversed between the samples: follow the new direction
      continue;
    }
    const double tMean = (t_[0] + t_[1] + t_[2]) / 3.0;
    const double qMean = (q_[0][k] + q_[1][k] + q_[2][k]) / 3.0;
    double num = 0.0, den = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
      num += (t_[i] - tMean) * (q_[i][k] - qMean);
      den += (t_[i] - tMean) * (t_[i] - tMean);
    }
    v[k] = den > 0.0 ? num / den : lastSlope;
  }
  for (double& x : v) {
    if (!std::isfinite(x)) x = 0.0;
  }
  return v;
}

std::array<double, 3> extrapolate(const std::array<double, 3>& qMm,
                                  const std::array<double, 3>& velocityMmS, double horizonS,
                                  const std::array<double, 3>& travelLoMm,
                                  const std::array<double, 3>& travelHiMm) noexcept {
  std::array<double, 3> out = qMm;
  for (std::size_t k = 0; k < 3; ++k) {
    const double ahead = qMm[k] + velocityMmS[k] * horizonS;
    if (!std::isfinite(ahead)) continue;
    const bool inside = qMm[k] >= travelLoMm[k] && qMm[k] <= travelHiMm[k];
    out[k] = inside ? std::clamp(ahead, travelLoMm[k], travelHiMm[k]) : ahead;
  }
  return out;
}

}  // namespace volcomp::loop
