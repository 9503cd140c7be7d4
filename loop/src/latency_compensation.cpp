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

// A vertex this little ahead of the newest read counts as at it (rounding of the fit).
constexpr double kAtTheNewestS = 1e-4;

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
  if (count_ == kHistorySamples) {
    first_ = index(1);
    --count_;
  }
  t_[index(count_)] = t;
  q_[index(count_)] = qMm;
  ++count_;
}

AxisVelocity VelocityEstimator::velocity(std::size_t k) const noexcept {
  const std::size_t n = std::min(count_, kVelocitySamples);
  if (n < 3) return {};
  const std::size_t from = count_ - n;
  // Times relative to the newest sample keep the sums well conditioned.
  const time_point origin = newest();
  double tMean = 0.0, qMean = 0.0;
  for (std::size_t i = from; i < count_; ++i) {
    tMean += seconds(t_[index(i)] - origin);
    qMean += q_[index(i)][k];
  }
  tMean /= static_cast<double>(n);
  qMean /= static_cast<double>(n);
  double num = 0.0, den = 0.0;
  for (std::size_t i = from; i < count_; ++i) {
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
  for (std::size_t i = from + 1; i < count_; ++i) {
    if (sign(q_[index(i)][k] - q_[index(i - 1)][k]) != s) return {};
  }
  // The smaller of the two: a deceleration shows in the newest pair before the fit.
  return {true, std::abs(last) < std::abs(fit) ? last : fit};
}

AxisParabola VelocityEstimator::parabola(std::size_t k, double floorMm,
                                         std::size_t samples) const noexcept {
  AxisParabola p;
  const std::size_t n = std::min(samples, count_);
  if (n < 5) return p;
  const time_point origin = newest();
  const double spanS = -seconds(t_[index(0)] - origin);
  if (!(spanS > 0.0)) return p;
  // x = t / span in [-1, 0] and y = q - q_newest keep the 3 x 3 normal equations well scaled.
  const double y0 = q_[index(count_ - 1)][k];
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, r0 = 0, r1 = 0, r2 = 0;
  double lo = q_[index(0)][k], hi = lo;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = seconds(t_[index(i)] - origin) / spanS, y = q_[index(i)][k] - y0;
    const double x2 = x * x;
    s0 += 1;
    s1 += x;
    s2 += x2;
    s3 += x2 * x;
    s4 += x2 * x2;
    r0 += y;
    r1 += x * y;
    r2 += x2 * y;
    lo = std::min(lo, q_[index(i)][k]);
    hi = std::max(hi, q_[index(i)][k]);
  }
  // Cramer's rule on [s0 s1 s2; s1 s2 s3; s2 s3 s4] c = r.
  const auto det3 = [](double a, double b, double c, double d, double e, double f, double g,
                       double h, double i) {
    return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  };
  const double det = det3(s0, s1, s2, s1, s2, s3, s2, s3, s4);
  if (!(std::abs(det) > 1e-12)) return p;
  const double a0 = det3(r0, s1, s2, r1, s2, s3, r2, s3, s4) / det;
  const double a1 = det3(s0, r0, s2, s1, r1, s3, s2, r2, s4) / det;
  const double a2 = det3(s0, s1, r0, s1, s2, r1, s2, s3, r2) / det;
  double sumSq = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = seconds(t_[index(i)] - origin) / spanS, y = q_[index(i)][k] - y0;
    const double r = a0 + a1 * x + a2 * x * x - y;
    sumSq += r * r;
  }
  const double residual = std::sqrt(sumSq / static_cast<double>(n));
  p.rangeMm = hi - lo;
  p.c0 = y0 + a0;
  p.c1 = a1 / spanS;
  p.c2 = a2 / (spanS * spanS);
  p.oldestS = -spanS;
  p.smooth =
      std::isfinite(p.c1) && std::isfinite(p.c2) && residual <= std::max(0.02 * p.rangeMm, floorMm);
  return p;
}

double VelocityEstimator::sinceNewestS(std::size_t i) const noexcept {
  return seconds(t_[index(i)] - newest());
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

HoldPrediction predictHold(const VelocityEstimator& estimator, const std::array<double, 3>& qMm,
                           const model::Directions& tracked, std::chrono::nanoseconds horizon,
                           std::chrono::nanoseconds period, std::chrono::nanoseconds maxHorizon,
                           double minSpanMm) noexcept {
  HoldPrediction hold;
  hold.qMm = qMm;
  hold.directions = tracked;
  hold.extrapolated =
      predictPositions(estimator, hold.qMm, hold.directions, horizon, maxHorizon, minSpanMm);
  const double hS = seconds(std::clamp(horizon, std::chrono::nanoseconds(0), maxHorizon));
  const double periodS = seconds(period);
  const double startS = hS - periodS / 2.0, endS = hS + periodS / 2.0;
  const auto towards = [](double v) {
    return v > 0.0 ? model::Direction::Positive : model::Direction::Negative;
  };
  for (std::size_t k = 0; k < 3; ++k) {
    // Every prediction needs a full window: the parabola of the reads before the newest, and
    // the newest read to check it against.
    if (estimator.size() < kHistorySamples) continue;
    const AxisParabola before = estimator.parabola(k, minSpanMm, kHistorySamples - 1);
    if (!before.smooth || !(before.rangeMm > 10.0 * minSpanMm) || before.c2 == 0.0) continue;
    // An event (a turn, or a stop and on) between the two newest reads, or at the newest: the
    // tracker cannot have seen it yet. After a turn the newest read lies back from the vertex of
    // the parabola of the reads before; after a stop and on in the same direction beyond it. Only
    // a clear step beyond (half the hysteresis) is taken as going on: a read too close to the
    // vertex to tell is taken as the turn the previous cycle predicted.
    const double vertexS = -before.c1 / (2.0 * before.c2);
    if (vertexS > estimator.sinceNewestS(kHistorySamples - 2) && vertexS <= kAtTheNewestS) {
      const double vertexMm = before.c0 + before.c1 * vertexS + before.c2 * vertexS * vertexS;
      const double approach = before.c2 < 0.0 ? 1.0 : -1.0;  // the direction into the vertex
      if ((qMm[k] - vertexMm) * approach > 0.5 * minSpanMm) continue;
      if (hold.qMm[k] == qMm[k]) ++hold.extrapolated;
      hold.qMm[k] = before.c0 + before.c1 * hS + before.c2 * hS * hS;
      hold.directions[k] = towards(-approach);
      continue;
    }
    // Otherwise the newest read must continue the parabola of the reads before (a stop and on a
    // read ago bends it away, and is no turn ahead).
    if (!(std::abs(qMm[k] - before.c0) <= std::max(0.02 * before.rangeMm, minSpanMm))) continue;
    // Braking towards a turn ahead, smoothly, the velocity estimate agreeing on the direction.
    // At rest (noise, a few counts) there is no turn to predict: the tracker's hysteresis rules.
    const AxisParabola p = estimator.parabola(k, minSpanMm);
    if (!p.smooth || !(p.rangeMm > 10.0 * minSpanMm) || p.c2 == 0.0 || p.c1 == 0.0) continue;
    const double turnS = -p.c1 / (2.0 * p.c2);
    const AxisVelocity v = estimator.velocity(k);
    if (!(turnS > 0.0) || !v.sure || sign(v.mmS) != sign(p.c1) || turnS >= endS) continue;
    if (hold.qMm[k] == qMm[k]) ++hold.extrapolated;
    hold.qMm[k] = p.c0 + p.c1 * hS + p.c2 * hS * hS;
    if (turnS <= startS) {
      hold.directions[k] = towards(-p.c1);
    } else {
      hold.directions[k] = towards(p.c1);
      hold.turnAxis[hold.turns] = k;
      hold.turnFraction[hold.turns] = (turnS - startS) / periodS;
      ++hold.turns;
    }
  }
  // Ascending fractions, so the loop can walk the hold's pieces in order (at most three).
  for (std::size_t i = 1; i < hold.turns; ++i) {
    for (std::size_t j = i; j > 0 && hold.turnFraction[j] < hold.turnFraction[j - 1]; --j) {
      std::swap(hold.turnFraction[j], hold.turnFraction[j - 1]);
      std::swap(hold.turnAxis[j], hold.turnAxis[j - 1]);
    }
  }
  return hold;
}

}  // namespace volcomp::loop
