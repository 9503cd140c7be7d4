#include "volcomp/metrology/iso230_2.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"

namespace volcomp::metrology {
namespace {

using config::ConfigError;

constexpr double kSameTargetMm = 1e-6;

std::string mm(double value) {
  std::ostringstream text;
  text.precision(10);
  text << value << " mm";
  return text.str();
}

const char* arrow(model::Direction direction) {
  return direction == model::Direction::Positive ? "\xE2\x86\x91" : "\xE2\x86\x93";
}

/// Distinct target positions, ascending, readings closer than kSameTargetMm merged.
std::vector<double> distinctTargets(const PositioningRuns& runs) {
  std::vector<double> all;
  all.reserve(runs.samples.size());
  for (const PositioningSample& sample : runs.samples) all.push_back(sample.targetMm);
  std::sort(all.begin(), all.end());
  std::vector<double> targets;
  for (double value : all) {
    if (targets.empty() || value - targets.back() > kSameTargetMm) targets.push_back(value);
  }
  return targets;
}

std::size_t targetIndex(const std::vector<double>& targets, double valueMm) {
  const auto it = std::lower_bound(targets.begin(), targets.end(), valueMm - kSameTargetMm);
  return static_cast<std::size_t>(it - targets.begin());
}

struct Pass {
  std::vector<std::optional<double>> deviationsMm;
  std::vector<int> lines;
};

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double sampleStandardDeviation(const std::vector<double>& values, double meanValue) {
  double sum = 0.0;
  for (double v : values) sum += (v - meanValue) * (v - meanValue);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

void warnAboutTargets(const std::vector<double>& targets, std::vector<std::string>& warnings) {
  const double travelMm = targets.back() - targets.front();
  std::vector<double> intervals;
  for (std::size_t i = 1; i < targets.size(); ++i) intervals.push_back(targets[i] - targets[i - 1]);
  const auto [shortest, longest] = std::minmax_element(intervals.begin(), intervals.end());
  if (*longest - *shortest <= 1e-3 * *longest) {
    warnings.push_back(
        "the target positions are evenly spaced (every interval " + mm(intervals.front()) +
        "): ISO 230-2 asks for unequal intervals (P_i = (i-1) p + r_i with a different r_i at "
        "each target) so that periodic errors such as the leadscrew pitch or the scale "
        "graduation are not all sampled at the same phase");
  }
  const double perMetre = static_cast<double>(targets.size()) / (travelMm / 1000.0);
  if (travelMm <= 2000.0 && perMetre < 5.0 - 1e-9) {
    std::ostringstream text;
    text.precision(3);
    text << "only " << perMetre << " target positions per metre of the " << mm(travelMm)
         << " measurement travel: ISO 230-2 asks for at least 5 per metre";
    warnings.push_back(text.str());
  }
  if (travelMm > 2000.0) {
    warnings.push_back("the measurement travel is " + mm(travelMm) +
                       ": ISO 230-2 tests axes over 2000 mm differently (the whole travel once in "
                       "each direction with about 250 mm intervals, repeatability over 2000 mm)");
  }
}

}  // namespace

Iso230Result evaluateIso230_2(const PositioningRuns& runs) {
  if (runs.samples.empty()) throw ConfigError(runs.file, "", "no readings");
  const std::vector<double> targets = distinctTargets(runs);
  const std::size_t m = targets.size();

  // Gather each pass (direction, run) and check that it visits every target exactly once.
  std::map<std::pair<int, int>, Pass> passes;
  for (const PositioningSample& sample : runs.samples) {
    Pass& pass = passes[{static_cast<int>(sample.direction), sample.run}];
    if (pass.deviationsMm.empty()) {
      pass.deviationsMm.resize(m);
      pass.lines.resize(m, 0);
    }
    const std::size_t i = targetIndex(targets, sample.targetMm);
    if (pass.deviationsMm[i]) {
      throw ConfigError(runs.file, "line " + std::to_string(sample.line),
                        "run " + std::to_string(sample.run) + " " + arrow(sample.direction) +
                            " has a second reading at target " + mm(targets[i]) +
                            " (first on line " + std::to_string(pass.lines[i]) + ")");
    }
    pass.deviationsMm[i] = sample.deviationMm;
    pass.lines[i] = sample.line;
  }
  for (const auto& [key, pass] : passes) {
    for (std::size_t i = 0; i < m; ++i) {
      if (pass.deviationsMm[i]) continue;
      throw ConfigError(
          runs.file, "",
          "unequal targets: run " + std::to_string(key.second) + " " +
              arrow(static_cast<model::Direction>(key.first)) + " has no reading at target " +
              mm(targets[i]) +
              " (ISO 230-2 needs every run to visit the same target positions in both directions)");
    }
  }

  Iso230Result result;
  result.source = runs.file;
  result.axis = runs.axis;
  for (const auto& [key, pass] : passes) {
    (key.first > 0 ? result.runsPositive : result.runsNegative).push_back(key.second);
  }
  const auto requireRuns = [&](const std::vector<int>& list, model::Direction direction) {
    if (static_cast<int>(list.size()) >= kMinimumRuns) return;
    throw ConfigError(runs.file, "",
                      std::to_string(list.size()) + " run(s) in the " +
                          (direction == model::Direction::Positive ? "positive (\xE2\x86\x91)"
                                                                   : "negative (\xE2\x86\x93)") +
                          " direction: ISO 230-2 needs at least " + std::to_string(kMinimumRuns) +
                          " runs in each direction");
  };
  requireRuns(result.runsPositive, model::Direction::Positive);
  requireRuns(result.runsNegative, model::Direction::Negative);
  if (static_cast<int>(m) < kMinimumTargets) {
    throw ConfigError(runs.file, "",
                      std::to_string(m) + " target position(s): ISO 230-2 needs at least " +
                          std::to_string(kMinimumTargets));
  }
  if (result.runsPositive.size() != result.runsNegative.size()) {
    result.warnings.push_back(std::to_string(result.runsPositive.size()) + " runs " +
                              "\xE2\x86\x91 but " + std::to_string(result.runsNegative.size()) +
                              " runs \xE2\x86\x93: the standard test has the same number in "
                              "both directions");
  }
  warnAboutTargets(targets, result.warnings);
  if (!runs.ignoredColumns.empty()) {
    // The names come from the file: quoted, and not more of them than a line can show.
    constexpr std::size_t kListed = 10;
    const std::vector<std::string>& ignored = runs.ignoredColumns;
    std::string list;
    for (std::size_t i = 0; i < ignored.size() && i < kListed; ++i) {
      list += (list.empty() ? "" : ", ") + config::quoted(ignored[i]);
    }
    if (ignored.size() > kListed) {
      list += " and " + std::to_string(ignored.size() - kListed) + " more";
    }
    result.warnings.push_back("columns not used: " + list);
  }

  // Per target.
  for (std::size_t i = 0; i < m; ++i) {
    TargetFigures t;
    t.positionMm = targets[i];
    for (int run : result.runsPositive) {
      t.deviationsPositiveMm.push_back(*passes.at({1, run}).deviationsMm[i]);
    }
    for (int run : result.runsNegative) {
      t.deviationsNegativeMm.push_back(*passes.at({-1, run}).deviationsMm[i]);
    }
    t.meanPositiveMm = mean(t.deviationsPositiveMm);
    t.meanNegativeMm = mean(t.deviationsNegativeMm);
    t.meanBidirectionalMm = 0.5 * (t.meanPositiveMm + t.meanNegativeMm);
    t.reversalMm = t.meanPositiveMm - t.meanNegativeMm;
    t.sPositiveMm = sampleStandardDeviation(t.deviationsPositiveMm, t.meanPositiveMm);
    t.sNegativeMm = sampleStandardDeviation(t.deviationsNegativeMm, t.meanNegativeMm);
    t.repeatabilityPositiveMm = 4.0 * t.sPositiveMm;
    t.repeatabilityNegativeMm = 4.0 * t.sNegativeMm;
    t.repeatabilityBidirectionalMm =
        std::max({2.0 * t.sPositiveMm + 2.0 * t.sNegativeMm + std::abs(t.reversalMm),
                  t.repeatabilityPositiveMm, t.repeatabilityNegativeMm});
    result.targets.push_back(std::move(t));
  }

  // Per axis.
  AxisFigures& a = result.figures;
  const auto maxOf = [&](auto f) {
    double best = f(result.targets.front());
    for (const TargetFigures& t : result.targets) best = std::max(best, f(t));
    return best;
  };
  const auto minOf = [&](auto f) {
    double best = f(result.targets.front());
    for (const TargetFigures& t : result.targets) best = std::min(best, f(t));
    return best;
  };
  a.reversalMm = maxOf([](const TargetFigures& t) { return std::abs(t.reversalMm); });
  double reversalSum = 0.0;
  for (const TargetFigures& t : result.targets) reversalSum += t.reversalMm;
  a.meanReversalMm = reversalSum / static_cast<double>(m);
  a.repeatabilityPositiveMm =
      maxOf([](const TargetFigures& t) { return t.repeatabilityPositiveMm; });
  a.repeatabilityNegativeMm =
      maxOf([](const TargetFigures& t) { return t.repeatabilityNegativeMm; });
  a.repeatabilityBidirectionalMm =
      maxOf([](const TargetFigures& t) { return t.repeatabilityBidirectionalMm; });
  const auto up = [](const TargetFigures& t) { return t.meanPositiveMm; };
  const auto down = [](const TargetFigures& t) { return t.meanNegativeMm; };
  a.systematicPositiveMm = maxOf(up) - minOf(up);
  a.systematicNegativeMm = maxOf(down) - minOf(down);
  a.systematicBidirectionalMm = std::max(maxOf(up), maxOf(down)) - std::min(minOf(up), minOf(down));
  const auto both = [](const TargetFigures& t) { return t.meanBidirectionalMm; };
  a.meanBidirectionalRangeMm = maxOf(both) - minOf(both);
  const auto upHigh = [](const TargetFigures& t) { return t.meanPositiveMm + 2.0 * t.sPositiveMm; };
  const auto upLow = [](const TargetFigures& t) { return t.meanPositiveMm - 2.0 * t.sPositiveMm; };
  const auto downHigh = [](const TargetFigures& t) {
    return t.meanNegativeMm + 2.0 * t.sNegativeMm;
  };
  const auto downLow = [](const TargetFigures& t) {
    return t.meanNegativeMm - 2.0 * t.sNegativeMm;
  };
  a.accuracyPositiveMm = maxOf(upHigh) - minOf(upLow);
  a.accuracyNegativeMm = maxOf(downHigh) - minOf(downLow);
  a.accuracyBidirectionalMm =
      std::max(maxOf(upHigh), maxOf(downHigh)) - std::min(minOf(upLow), minOf(downLow));
  return result;
}

}  // namespace volcomp::metrology
