#include "volcomp/loop/latency_compensation.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::loop {
namespace {

double seconds(std::chrono::nanoseconds d) noexcept {
  return std::chrono::duration<double>(d).count();
}

int sign(double x) noexcept {
  return (x > 0.0) - (x < 0.0);
}

}  // namespace

void VelocityEstimator::add(time_point t, const std::array<double, 3>& qMm,
                            std::chrono::nanoseconds maxGap) noexcept {
  if (count_ > 0) {
    const time_point last = newest();
    if (t <= last) {
      // The same moment read twice (a repeated read of one cycle): keep the newer values.
      q_[index(count_ - 1)] = qMm;
      return;
    }
    if (t - last > maxGap) count_ = 0;
  }
  if (count_ == kVelocitySamples) {
    first_ = index(1);
    --count_;
  }
  t_[index(count_)] = t;
  q_[index(count_)] = qMm;
  ++count_;
}

AxisVelocity VelocityEstimator::velocity(std::size_t k) const noexcept {
  if (count_ < 3) return {};
  // Times relative to the newest sample keep the sums well conditioned.
  const time_point origin = newest();
  double tMean = 0.0, qMean = 0.0;
  for (std::size_t i = 0; i < count_; ++i) {
    tMean += seconds(t_[index(i)] - origin);
    qMean += q_[index(i)][k];
  }
  tMean /= static_cast<double>(count_);
  qMean /= static_cast<double>(count_);
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < count_; ++i) {
    const double dt = seconds(t_[index(i)] - origin) - tMean;
    num += dt * (q_[index(i)][k] - qMean);
    den += dt * dt;
  }
  if (!(den > 0.0)) return {};
  const double fit = num / den;
  const std::size_t a = index(count_ - 2), b = index(count_ - 1);
  const double last = (q_[b][k] - q_[a][k]) / seconds(t_[b] - t_[a]);
  const int s = sign(fit);
  if (s == 0 || sign(last) != s || !std::isfinite(fit) || !std::isfinite(last)) return {};
  // Every step of the window in the same direction: a reversal or a stop inside it (a step of
  // zero or against the fit) makes the estimate unsure, whatever the fit says.
  for (std::size_t i = 1; i < count_; ++i) {
    if (sign(q_[index(i)][k] - q_[index(i - 1)][k]) != s) return {};
  }
  // The smaller of the two: a deceleration shows in the newest pair before the fit.
  return {true, std::abs(last) < std::abs(fit) ? last : fit};
}

int predictPositions(const VelocityEstimator& estimator, std::array<double, 3>& qMm,
                     model::Directions& directions, std::chrono::nanoseconds horizon,
                     std::chrono::nanoseconds maxHorizon, double minSpanMm) noexcept {
  const double hS = seconds(std::clamp(horizon, std::chrono::nanoseconds(0), maxHorizon));
  int extrapolated = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const AxisVelocity v = estimator.velocity(k);
    if (!v.sure || !(std::abs(estimator.spanMm(k)) > minSpanMm)) continue;
    qMm[k] += v.mmS * hS;
    directions[k] = v.mmS > 0.0 ? model::Direction::Positive : model::Direction::Negative;
    ++extrapolated;
  }
  return extrapolated;
}

}  // namespace volcomp::loop
