// ISO 230-2 figures on larger random data sets against an independent implementation written
// here from the standard's definitions: one pass per target with Welford's running mean and
// variance in long double, the axis figures from explicit lists of the per-target values, and the
// data handed over as PositioningSamples in shuffled order (not through the CSV reader).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "volcomp/metrology/iso230_2.hpp"

namespace volcomp::metrology {
namespace {

struct Reference {
  std::vector<double> up, down, sUp, sDown;
  double B = 0, Bbar = 0, Rup = 0, Rdown = 0, R = 0, Eup = 0, Edown = 0, E = 0, M = 0, Aup = 0,
         Adown = 0, A = 0;
  std::vector<double> Ri;
};

/// Welford: mean and sample standard deviation.
std::pair<double, double> welford(const std::vector<double>& values) {
  long double mean = 0, m2 = 0;
  long double n = 0;
  for (double v : values) {
    n += 1;
    const long double delta = v - mean;
    mean += delta / n;
    m2 += delta * (v - mean);
  }
  return {static_cast<double>(mean), static_cast<double>(std::sqrt(m2 / (n - 1)))};
}

double range(const std::vector<double>& a) {
  return *std::max_element(a.begin(), a.end()) - *std::min_element(a.begin(), a.end());
}

Reference reference(const std::vector<std::vector<double>>& up,
                    const std::vector<std::vector<double>>& down) {
  Reference r;
  std::vector<double> Bi, mid, highUp, lowUp, highDown, lowDown, Rup, Rdown;
  for (std::size_t i = 0; i < up.size(); ++i) {
    const auto [mu, su] = welford(up[i]);
    const auto [md, sd] = welford(down[i]);
    r.up.push_back(mu);
    r.down.push_back(md);
    r.sUp.push_back(su);
    r.sDown.push_back(sd);
    Bi.push_back(mu - md);
    mid.push_back((mu + md) / 2);
    highUp.push_back(mu + 2 * su);
    lowUp.push_back(mu - 2 * su);
    highDown.push_back(md + 2 * sd);
    lowDown.push_back(md - 2 * sd);
    Rup.push_back(4 * su);
    Rdown.push_back(4 * sd);
    double ri = 2 * su + 2 * sd + std::abs(mu - md);
    if (4 * su > ri) ri = 4 * su;
    if (4 * sd > ri) ri = 4 * sd;
    r.Ri.push_back(ri);
  }
  for (double b : Bi) r.B = std::max(r.B, std::abs(b));
  long double sum = 0;
  for (double b : Bi) sum += b;
  r.Bbar = static_cast<double>(sum / static_cast<long double>(Bi.size()));
  r.Rup = *std::max_element(Rup.begin(), Rup.end());
  r.Rdown = *std::max_element(Rdown.begin(), Rdown.end());
  r.R = *std::max_element(r.Ri.begin(), r.Ri.end());
  r.Eup = range(r.up);
  r.Edown = range(r.down);
  std::vector<double> both = r.up;
  both.insert(both.end(), r.down.begin(), r.down.end());
  r.E = range(both);
  r.M = range(mid);
  r.Aup = *std::max_element(highUp.begin(), highUp.end()) -
          *std::min_element(lowUp.begin(), lowUp.end());
  r.Adown = *std::max_element(highDown.begin(), highDown.end()) -
            *std::min_element(lowDown.begin(), lowDown.end());
  std::vector<double> high = highUp, low = lowUp;
  high.insert(high.end(), highDown.begin(), highDown.end());
  low.insert(low.end(), lowDown.begin(), lowDown.end());
  r.A = *std::max_element(high.begin(), high.end()) - *std::min_element(low.begin(), low.end());
  return r;
}

TEST(Iso230Random, AgreesWithAnIndependentImplementation) {
  std::mt19937_64 rng(20260230);
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(trial);
    std::uniform_int_distribution<int> targetCount(5, 41), runCount(5, 12);
    const int m = targetCount(rng);
    const int nUp = runCount(rng);
    const int nDown = trial % 3 == 0 ? nUp : runCount(rng);
    std::uniform_real_distribution<double> gap(3.0, 60.0), level(-0.02, 0.02), noise(-0.004, 0.004);
    std::vector<double> targets{std::uniform_real_distribution<double>(-500, 500)(rng)};
    for (int i = 1; i < m; ++i) targets.push_back(targets.back() + gap(rng));
    std::vector<std::vector<double>> up(m), down(m);
    PositioningRuns runs;
    runs.file = "random";
    for (int i = 0; i < m; ++i) {
      const double base = level(rng);
      const double reversal = level(rng) / 4;
      for (int j = 0; j < nUp; ++j) {
        up[i].push_back(base + noise(rng));
        runs.samples.push_back(
            {targets[i], 10 + 3 * j, model::Direction::Positive, up[i].back(), 0});
      }
      for (int j = 0; j < nDown; ++j) {
        down[i].push_back(base - reversal + noise(rng));
        runs.samples.push_back(
            {targets[i], 100 - j, model::Direction::Negative, down[i].back(), 0});
      }
    }
    // Run numbers ascend in the result; the reference's down runs were numbered downwards.
    for (auto& d : down) std::reverse(d.begin(), d.end());
    std::shuffle(runs.samples.begin(), runs.samples.end(), rng);
    const Iso230Result r = evaluateIso230_2(runs);
    const Reference ref = reference(up, down);
    constexpr double tol = 1e-15;
    ASSERT_EQ(r.targets.size(), static_cast<std::size_t>(m));
    for (int i = 0; i < m; ++i) {
      const TargetFigures& t = r.targets[static_cast<std::size_t>(i)];
      EXPECT_DOUBLE_EQ(t.positionMm, targets[static_cast<std::size_t>(i)]);
      EXPECT_EQ(t.deviationsPositiveMm, up[static_cast<std::size_t>(i)]);
      EXPECT_EQ(t.deviationsNegativeMm, down[static_cast<std::size_t>(i)]);
      EXPECT_NEAR(t.meanPositiveMm, ref.up[i], tol);
      EXPECT_NEAR(t.meanNegativeMm, ref.down[i], tol);
      EXPECT_NEAR(t.sPositiveMm, ref.sUp[i], tol);
      EXPECT_NEAR(t.sNegativeMm, ref.sDown[i], tol);
      EXPECT_NEAR(t.repeatabilityBidirectionalMm, ref.Ri[i], 4 * tol);
    }
    const AxisFigures& a = r.figures;
    EXPECT_NEAR(a.reversalMm, ref.B, tol);
    EXPECT_NEAR(a.meanReversalMm, ref.Bbar, tol);
    EXPECT_NEAR(a.repeatabilityPositiveMm, ref.Rup, 4 * tol);
    EXPECT_NEAR(a.repeatabilityNegativeMm, ref.Rdown, 4 * tol);
    EXPECT_NEAR(a.repeatabilityBidirectionalMm, ref.R, 4 * tol);
    EXPECT_NEAR(a.systematicPositiveMm, ref.Eup, tol);
    EXPECT_NEAR(a.systematicNegativeMm, ref.Edown, tol);
    EXPECT_NEAR(a.systematicBidirectionalMm, ref.E, tol);
    EXPECT_NEAR(a.meanBidirectionalRangeMm, ref.M, tol);
    EXPECT_NEAR(a.accuracyPositiveMm, ref.Aup, 4 * tol);
    EXPECT_NEAR(a.accuracyNegativeMm, ref.Adown, 4 * tol);
    EXPECT_NEAR(a.accuracyBidirectionalMm, ref.A, 4 * tol);
    EXPECT_EQ(r.runsPositive.size(), static_cast<std::size_t>(nUp));
    EXPECT_EQ(r.runsNegative.size(), static_cast<std::size_t>(nDown));
  }
}

}  // namespace
}  // namespace volcomp::metrology
