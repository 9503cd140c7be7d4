// ISO 230-2 figures against values worked out by hand.
//
// Data set (deviations in um; 5 runs per direction; run j takes offset o_j = (-1, -1, 0, +1, +1)
// times a spread, so that the mean is the base value and s = spread exactly:
// Σ o_j² = 4, s² = 4 spread² / (5 - 1) = spread²):
//
//   i  P_i (mm)  x̄_i↑  spread↑ = s_i↑   x̄_i↓  spread↓ = s_i↓
//   1   0.0        0       1.0            4       0.5
//   2  10.5        2       0.5            5       1.0
//   3  19.8        3       1.0            7       2.0
//   4  31.2        1       2.0            3       0.5
//   5  40.0       -1       0.5            2       1.0
//
// Per target:                   i=1   i=2   i=3   i=4   i=5
//   x̄_i = (x̄↑ + x̄↓)/2          2     3.5   5     2     0.5
//   B_i = x̄↑ - x̄↓               -4    -3    -4    -2    -3
//   R_i↑ = 4 s↑                  4     2     4     8     2
//   R_i↓ = 4 s↓                  2     4     8     2     4
//   2s↑ + 2s↓ + |B_i|            7     6     10    7     6
//   R_i = max of the three       7     6     10    8     6
// Per axis:
//   B  = max |B_i| = 4;  B̄ = (-4 - 3 - 4 - 2 - 3) / 5 = -3.2
//   R↑ = 8, R↓ = 8, R = 10
//   E↑ = 3 - (-1) = 4;  E↓ = 7 - 2 = 5;  E = max(3, 7) - min(-1, 2) = 8
//   M  = 5 - 0.5 = 4.5
//   x̄↑ + 2s↑ = 2, 3, 5, 5, 0      x̄↑ - 2s↑ = -2, 1, 1, -3, -2    A↑ = 5 - (-3) = 8
//   x̄↓ + 2s↓ = 5, 7, 11, 4, 4     x̄↓ - 2s↓ = 3, 3, 3, 2, 0       A↓ = 11 - 0 = 11
//   A = max(5, 11) - min(-3, 0) = 14

#include <gtest/gtest.h>

#include <array>
#include <sstream>

#include "volcomp/config/config_error.hpp"
#include "volcomp/metrology/iso230_2.hpp"
#include "volcomp/metrology/iso230_2_json.hpp"
#include "volcomp/metrology/positioning_runs.hpp"

namespace volcomp::metrology {
namespace {

constexpr double kUm = 1e-3;
constexpr double kTol = 1e-12;

struct Row {
  double target, meanUp, spreadUp, meanDown, spreadDown;
};
const Row kRows[] = {{0.0, 0, 1.0, 4, 0.5},
                     {10.5, 2, 0.5, 5, 1.0},
                     {19.8, 3, 1.0, 7, 2.0},
                     {31.2, 1, 2.0, 3, 0.5},
                     {40.0, -1, 0.5, 2, 1.0}};
const double kOffsets[] = {-1, -1, 0, 1, 1};

std::string handCsv() {
  std::ostringstream csv;
  csv << "# hand-worked data set\nrun,direction,target_mm,deviation_um\n";
  for (int run = 1; run <= 5; ++run) {
    for (const Row& r : kRows) {
      csv << run << ",+," << r.target << ',' << r.meanUp + kOffsets[run - 1] * r.spreadUp << '\n';
    }
    for (int i = 4; i >= 0; --i) {
      const Row& r = kRows[i];
      csv << run << ",-," << r.target << ',' << r.meanDown + kOffsets[run - 1] * r.spreadDown
          << '\n';
    }
  }
  return csv.str();
}

Iso230Result evaluateHand() {
  std::istringstream in(handCsv());
  return evaluateIso230_2(parsePositioningCsv(in, "hand.csv", model::Axis::X));
}

/// Axis figures in um in the order B, B̄, R↑, R↓, R, E↑, E↓, E, M, A↑, A↓, A.
void expectAxisFigures(const AxisFigures& a, const std::array<double, 12>& um) {
  const double actual[] = {a.reversalMm,
                           a.meanReversalMm,
                           a.repeatabilityPositiveMm,
                           a.repeatabilityNegativeMm,
                           a.repeatabilityBidirectionalMm,
                           a.systematicPositiveMm,
                           a.systematicNegativeMm,
                           a.systematicBidirectionalMm,
                           a.meanBidirectionalRangeMm,
                           a.accuracyPositiveMm,
                           a.accuracyNegativeMm,
                           a.accuracyBidirectionalMm};
  const char* names[] = {"B",      "B mean", "R up", "R down", "R",      "E up",
                         "E down", "E",      "M",    "A up",   "A down", "A"};
  for (std::size_t i = 0; i < 12; ++i) EXPECT_NEAR(actual[i], um[i] * kUm, kTol) << names[i];
}

TEST(Iso230Hand, PerTargetFiguresMatchTheWorkedValues) {
  const Iso230Result r = evaluateHand();
  ASSERT_EQ(r.targets.size(), 5u);
  const double mean[] = {2, 3.5, 5, 2, 0.5};
  const double reversal[] = {-4, -3, -4, -2, -3};
  const double repeatUp[] = {4, 2, 4, 8, 2};
  const double repeatDown[] = {2, 4, 8, 2, 4};
  const double repeat[] = {7, 6, 10, 8, 6};
  for (std::size_t i = 0; i < 5; ++i) {
    const TargetFigures& t = r.targets[i];
    SCOPED_TRACE(i);
    EXPECT_DOUBLE_EQ(t.positionMm, kRows[i].target);
    EXPECT_NEAR(t.meanPositiveMm, kRows[i].meanUp * kUm, kTol);
    EXPECT_NEAR(t.meanNegativeMm, kRows[i].meanDown * kUm, kTol);
    EXPECT_NEAR(t.meanBidirectionalMm, mean[i] * kUm, kTol);
    EXPECT_NEAR(t.reversalMm, reversal[i] * kUm, kTol);
    EXPECT_NEAR(t.sPositiveMm, kRows[i].spreadUp * kUm, kTol);
    EXPECT_NEAR(t.sNegativeMm, kRows[i].spreadDown * kUm, kTol);
    EXPECT_NEAR(t.repeatabilityPositiveMm, repeatUp[i] * kUm, kTol);
    EXPECT_NEAR(t.repeatabilityNegativeMm, repeatDown[i] * kUm, kTol);
    EXPECT_NEAR(t.repeatabilityBidirectionalMm, repeat[i] * kUm, kTol);
    ASSERT_EQ(t.deviationsPositiveMm.size(), 5u);
    EXPECT_NEAR(t.deviationsPositiveMm[0], (kRows[i].meanUp - kRows[i].spreadUp) * kUm, kTol);
  }
}

TEST(Iso230Hand, AxisFiguresMatchTheWorkedValues) {
  const Iso230Result r = evaluateHand();
  expectAxisFigures(r.figures, {4, -3.2, 8, 8, 10, 4, 5, 8, 4.5, 8, 11, 14});
  EXPECT_EQ(r.runsPositive, (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(r.runsNegative, (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(r.axis, model::Axis::X);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

// A second small set where B_i changes sign and the reversal of the axis is the largest |B_i|
// of a positive B_i (|B| is taken, not the signed maximum): ↑ means 5, 0, 0, 0, 0 um and ↓ means
// 0, 1, 1, 1, 1 um with no spread (s = 0): B_i = 5, -1, -1, -1, -1, B = 5, B̄ = 1/5 = 0.2,
// R_i = |B_i| (as 2s + 2s = 0), R = 5, R↑ = R↓ = 0; E↑ = 5, E↓ = 1, E = 5; x̄_i = 2.5, 0.5, ...
// so M = 2; A↑ = E↑ = 5, A↓ = E↓ = 1, A = 5.
TEST(Iso230Hand, ReversalOfTheAxisIsTheLargestMagnitude) {
  std::ostringstream csv;
  csv << "run,direction,target_mm,deviation_um\n";
  const double targets[] = {0, 12, 23, 37, 50};
  for (int run = 1; run <= 5; ++run) {
    for (int i = 0; i < 5; ++i)
      csv << run << ",up," << targets[i] << ',' << (i == 0 ? 5 : 0) << '\n';
    for (int i = 0; i < 5; ++i)
      csv << run << ",down," << targets[i] << ',' << (i == 0 ? 0 : 1) << '\n';
  }
  std::istringstream in(csv.str());
  const Iso230Result r = evaluateIso230_2(parsePositioningCsv(in, "b.csv"));
  expectAxisFigures(r.figures, {5, 0.2, 0, 0, 5, 5, 1, 5, 2, 5, 1, 5});
  EXPECT_FALSE(r.axis);
}

TEST(Iso230Json, HoldsEveryFigureUnderItsDocumentedKey) {
  const Iso230Result r = evaluateHand();
  const nlohmann::json j = toJson(r);
  EXPECT_EQ(j.at("format"), "volcomp-iso230-2/1");
  EXPECT_EQ(j.at("standard"), "ISO 230-2:2014");
  EXPECT_EQ(j.at("axis"), "X");
  EXPECT_EQ(j.at("units").at("deviation"), "mm");
  EXPECT_EQ(j.at("runs_positive").size(), 5u);
  ASSERT_EQ(j.at("targets").size(), 5u);
  const nlohmann::json& t = j.at("targets")[2];
  EXPECT_EQ(t.at("index"), 3);
  EXPECT_DOUBLE_EQ(t.at("position").get<double>(), 19.8);
  EXPECT_DOUBLE_EQ(t.at("mean_positive").get<double>(), r.targets[2].meanPositiveMm);
  EXPECT_DOUBLE_EQ(t.at("mean_negative").get<double>(), r.targets[2].meanNegativeMm);
  EXPECT_DOUBLE_EQ(t.at("mean_bidirectional").get<double>(), r.targets[2].meanBidirectionalMm);
  EXPECT_DOUBLE_EQ(t.at("reversal").get<double>(), r.targets[2].reversalMm);
  EXPECT_DOUBLE_EQ(t.at("s_positive").get<double>(), r.targets[2].sPositiveMm);
  EXPECT_DOUBLE_EQ(t.at("s_negative").get<double>(), r.targets[2].sNegativeMm);
  EXPECT_DOUBLE_EQ(t.at("repeatability_positive").get<double>(), 4 * kUm);
  EXPECT_DOUBLE_EQ(t.at("repeatability_negative").get<double>(), 8 * kUm);
  EXPECT_DOUBLE_EQ(t.at("repeatability_bidirectional").get<double>(), 10 * kUm);
  EXPECT_EQ(t.at("deviations_positive").size(), 5u);
  EXPECT_EQ(t.at("deviations_negative").size(), 5u);
  const nlohmann::json& a = j.at("axis_figures");
  const AxisFigures& f = r.figures;
  EXPECT_DOUBLE_EQ(a.at("reversal").get<double>(), f.reversalMm);
  EXPECT_DOUBLE_EQ(a.at("mean_reversal").get<double>(), f.meanReversalMm);
  EXPECT_DOUBLE_EQ(a.at("repeatability_positive").get<double>(), f.repeatabilityPositiveMm);
  EXPECT_DOUBLE_EQ(a.at("repeatability_negative").get<double>(), f.repeatabilityNegativeMm);
  EXPECT_DOUBLE_EQ(a.at("repeatability_bidirectional").get<double>(),
                   f.repeatabilityBidirectionalMm);
  EXPECT_DOUBLE_EQ(a.at("systematic_positive").get<double>(), f.systematicPositiveMm);
  EXPECT_DOUBLE_EQ(a.at("systematic_negative").get<double>(), f.systematicNegativeMm);
  EXPECT_DOUBLE_EQ(a.at("systematic_bidirectional").get<double>(), f.systematicBidirectionalMm);
  EXPECT_DOUBLE_EQ(a.at("mean_bidirectional_range").get<double>(), f.meanBidirectionalRangeMm);
  EXPECT_DOUBLE_EQ(a.at("accuracy_positive").get<double>(), f.accuracyPositiveMm);
  EXPECT_DOUBLE_EQ(a.at("accuracy_negative").get<double>(), f.accuracyNegativeMm);
  EXPECT_DOUBLE_EQ(a.at("accuracy_bidirectional").get<double>(), f.accuracyBidirectionalMm);
  EXPECT_TRUE(j.at("warnings").is_array());
}

}  // namespace
}  // namespace volcomp::metrology
