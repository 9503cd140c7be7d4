// Units and wording shared by the JSON report and the summary (see report.hpp).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "volcomp/calibration/report.hpp"

namespace volcomp::calibration {
namespace {

std::string perMm(const std::string& unit, int power) {
  if (power == 0) return unit;
  if (power == 1) return unit + "/mm";
  return unit + "/mm^" + std::to_string(power);
}

std::string componentLabel(const std::string& keyPath) {
  const std::string prefix = "components.";
  return keyPath.rfind(prefix, 0) == 0 ? keyPath.substr(prefix.size()) : keyPath;
}

std::string signedText(double value, int digits) {
  return (value >= 0.0 ? "+" : "") + significant(value, digits);
}

}  // namespace

std::string significant(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream out;
  out.precision(digits);
  out << value + 0.0;  // + 0.0: no "-0"
  return out.str();
}

DisplayUnit templateUnit(const ParameterInfo& info) {
  return {info.unit, info.toDisplay};
}

DisplayUnit screenUnit(bool angle, AngleDisplay angles) {
  if (!angle) return {"µm", 1e3};
  if (angles == AngleDisplay::Arcsecond) return {"arcsec", 648000.0 / std::numbers::pi};
  return {"µrad", 1e6};
}

DisplayUnit screenUnit(const ParameterInfo& info, AngleDisplay angles) {
  if (info.kind == ParameterInfo::Kind::Other) return templateUnit(info);
  DisplayUnit unit = screenUnit(info.kind == ParameterInfo::Kind::Angle, angles);
  unit.unit = perMm(unit.unit, info.perMmPower);
  return unit;
}

std::string physicalDescription(const Combination& combination,
                                const std::vector<ParameterInfo>& info, bool screen,
                                AngleDisplay angles) {
  const auto unitOf = [&](int j) {
    const ParameterInfo& p = info[static_cast<std::size_t>(j)];
    return screen ? screenUnit(p, angles) : templateUnit(p);
  };
  const ParameterInfo& pivot = info[static_cast<std::size_t>(combination.pivot)];
  const DisplayUnit pivotUnit = unitOf(combination.pivot);
  // One display unit of the pivot is 1 / factor internal units.
  const double step = 1.0 / pivotUnit.factor;
  std::ostringstream out;
  out << "1 " << pivotUnit.unit << " of " << pivot.name;
  // Runs of one component's parameters with the same step (the nodes of a table shifted
  // together) are named once: "+1 µrad of every node of EBY (6)".
  std::vector<std::string> others;
  const auto& terms = combination.rawTerms;
  for (std::size_t t = 0; t < terms.size();) {
    const int j = terms[t].first;
    if (j == combination.pivot) {
      ++t;
      continue;
    }
    const ParameterInfo& p = info[static_cast<std::size_t>(j)];
    const DisplayUnit unit = unitOf(j);
    const std::string stepText = signedText(terms[t].second * step * unit.factor, 3);
    std::size_t end = t + 1;
    while (end < terms.size() && terms[end].first != combination.pivot &&
           info[static_cast<std::size_t>(terms[end].first)].keyPath == p.keyPath &&
           signedText(terms[end].second * step * unitOf(terms[end].first).factor, 3) == stepText) {
      ++end;
    }
    const std::size_t run = end - t;
    std::string what = p.name;
    if (run >= 3) {
      const auto inComponent = static_cast<std::size_t>(
          std::count_if(info.begin(), info.end(),
                        [&](const ParameterInfo& q) { return q.keyPath == p.keyPath; }));
      const std::string& last = info[static_cast<std::size_t>(terms[end - 1].first)].name;
      what = run == inComponent ? "every parameter of " + componentLabel(p.keyPath) + " (" +
                                      std::to_string(run) + ")"
                                : p.name + " .. " + last + " (" + std::to_string(run) + ")";
    } else if (run == 2) {
      others.push_back(stepText + " " + unit.unit + " of " + p.name);
      what = info[static_cast<std::size_t>(terms[t + 1].first)].name;
    }
    std::string text = stepText + " " + unit.unit + " of " + what;
    // An angle of the pivot with a length: the length is the angle times a lever arm (mm).
    if (run == 1 && pivot.kind == ParameterInfo::Kind::Angle && pivot.perMmPower == 0 &&
        p.kind == ParameterInfo::Kind::Length && p.perMmPower == 0) {
      text += " (arm " + significant(std::abs(terms[t].second), 4) + " mm)";
    }
    others.push_back(text);
    t = end;
  }
  if (!others.empty()) out << " together with ";
  for (std::size_t t = 0; t < others.size(); ++t) {
    if (t > 0) out << (t + 1 == others.size() ? " and " : ", ");
    out << others[t];
  }
  const DisplayUnit length = screen ? screenUnit(false, angles) : DisplayUnit{"mm", 1.0};
  out << (others.empty() ? " changes" : " change") << " the measured residuals by "
      << significant(combination.residualChangePerPivotUnit * step * length.factor, 2) << " "
      << length.unit << " in all (root-sum-square over every residual)";
  return out.str();
}

PredictionSummary summarise(const std::vector<PointPrediction>& predictions) {
  PredictionSummary s;
  s.points = static_cast<int>(predictions.size());
  double sum = 0.0;
  int determined = 0;
  for (std::size_t i = 0; i < predictions.size(); ++i) {
    const PointPrediction& p = predictions[i];
    if (!p.determined) {
      ++s.undetermined;
      continue;
    }
    ++determined;
    const double radial = p.stdMm.norm();
    sum += radial * radial;
    if (radial > s.maxStdMm) {
      s.maxStdMm = radial;
      s.maxIndex = static_cast<int>(i);
    }
    s.maxAxisStdMm = s.maxAxisStdMm.cwiseMax(p.stdMm);
  }
  s.rmsStdMm = determined > 0 ? std::sqrt(sum / determined) : 0.0;
  return s;
}

}  // namespace volcomp::calibration
