#pragma once
/// ISO 230-2:2014 evaluation of the accuracy and repeatability of positioning of a linear axis
/// from bidirectional runs (clauses 3 and 7 of the standard). All lengths in mm.
///
/// Per target position P_i (i = 1..m), with x_ij↑ / x_ij↓ the deviations of run j (j = 1..n):
///   x̄_i↑ = (1/n) Σ_j x_ij↑,  x̄_i↓ likewise        mean unidirectional positional deviation
///   x̄_i  = (x̄_i↑ + x̄_i↓) / 2                      mean bidirectional positional deviation
///   B_i  = x̄_i↑ - x̄_i↓                            reversal value
///   s_i↑ = sqrt(Σ_j (x_ij↑ - x̄_i↑)² / (n - 1))    estimator of the unidirectional standard
///                                                  uncertainty of positioning (s_i↓ likewise)
///   R_i↑ = 4 s_i↑,  R_i↓ = 4 s_i↓                  unidirectional repeatability
///   R_i  = max(2 s_i↑ + 2 s_i↓ + |B_i|, R_i↑, R_i↓) bidirectional repeatability
/// Per axis:
///   B = max_i |B_i|,  B̄ = (1/m) Σ_i B_i           reversal value, mean reversal value
///   R↑ = max_i R_i↑,  R↓ = max_i R_i↓,  R = max_i R_i
///   E↑ = max x̄_i↑ - min x̄_i↑,  E↓ likewise,       systematic positional deviation
///   E  = max(x̄_i↑, x̄_i↓) - min(x̄_i↑, x̄_i↓)
///   M  = max x̄_i - min x̄_i                         range of the mean bidirectional deviation
///   A↑ = max(x̄_i↑ + 2 s_i↑) - min(x̄_i↑ - 2 s_i↑),  A↓ likewise    accuracy of positioning
///   A  = max(x̄_i↑ + 2 s_i↑, x̄_i↓ + 2 s_i↓) - min(x̄_i↑ - 2 s_i↑, x̄_i↓ - 2 s_i↓)
///
/// Refused (config::ConfigError naming the file and what is wrong): fewer than 5 runs in a
/// direction, fewer than 5 target positions, runs that do not all visit the same targets (a
/// missing or repeated reading), a direction without runs. Warned (Iso230Result::warnings): evenly
/// spaced targets (the standard asks for uneven intervals so that periodic errors are not sampled
/// at one phase), fewer than 5 targets per metre, a measurement travel over 2000 mm (the standard
/// tests long axes differently), different numbers of runs in the two directions.

#include <optional>
#include <string>
#include <vector>

#include "volcomp/metrology/positioning_runs.hpp"

namespace volcomp::metrology {

/// Figures at one target position P_i (mm).
struct TargetFigures {
  double positionMm = 0.0;
  /// x_ij↑ and x_ij↓ in the order of Iso230Result::runsPositive / runsNegative.
  std::vector<double> deviationsPositiveMm, deviationsNegativeMm;
  double meanPositiveMm = 0.0;                ///< x̄_i↑
  double meanNegativeMm = 0.0;                ///< x̄_i↓
  double meanBidirectionalMm = 0.0;           ///< x̄_i
  double reversalMm = 0.0;                    ///< B_i = x̄_i↑ - x̄_i↓ (signed)
  double sPositiveMm = 0.0;                   ///< s_i↑
  double sNegativeMm = 0.0;                   ///< s_i↓
  double repeatabilityPositiveMm = 0.0;       ///< R_i↑ = 4 s_i↑
  double repeatabilityNegativeMm = 0.0;       ///< R_i↓ = 4 s_i↓
  double repeatabilityBidirectionalMm = 0.0;  ///< R_i
};

/// Figures of the axis (mm).
struct AxisFigures {
  double reversalMm = 0.0;                    ///< B = max |B_i| (>= 0)
  double meanReversalMm = 0.0;                ///< B̄ = mean of B_i (signed)
  double repeatabilityPositiveMm = 0.0;       ///< R↑
  double repeatabilityNegativeMm = 0.0;       ///< R↓
  double repeatabilityBidirectionalMm = 0.0;  ///< R
  double systematicPositiveMm = 0.0;          ///< E↑
  double systematicNegativeMm = 0.0;          ///< E↓
  double systematicBidirectionalMm = 0.0;     ///< E
  double meanBidirectionalRangeMm = 0.0;      ///< M
  double accuracyPositiveMm = 0.0;            ///< A↑
  double accuracyNegativeMm = 0.0;            ///< A↓
  double accuracyBidirectionalMm = 0.0;       ///< A
};

struct Iso230Result {
  std::string source;               ///< file the runs came from
  std::optional<model::Axis> axis;  ///< when the runs name it
  /// Run numbers as in the file, ascending, per direction (n↑ = runsPositive.size()).
  std::vector<int> runsPositive, runsNegative;
  /// Ascending target positions.
  std::vector<TargetFigures> targets;
  AxisFigures figures;
  std::vector<std::string> warnings;
};

/// Smallest number of runs per direction and of target positions the standard allows.
inline constexpr int kMinimumRuns = 5;
inline constexpr int kMinimumTargets = 5;

/// Evaluates the runs. Readings whose targets differ by less than 1e-6 mm are the same target.
/// Throws config::ConfigError (file = runs.file) when the standard does not allow the data.
Iso230Result evaluateIso230_2(const PositioningRuns& runs);

}  // namespace volcomp::metrology
