// The readable summary of a calibration (see report.hpp): screen units, 3-4 significant digits.

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>
#include <tuple>

#include "volcomp/calibration/report.hpp"

namespace volcomp::calibration {
namespace {

constexpr std::size_t kListedCombinations = 12;

std::string um(double mm) {
  return significant(mm * 1e3, 4) + " µm";
}

std::string lineText(const std::vector<int>& lines, int index) {
  if (index >= 0 && static_cast<std::size_t>(index) < lines.size()) {
    return " (line " + std::to_string(lines[static_cast<std::size_t>(index)]) + ")";
  }
  return {};
}

std::string axisNames(int rows) {
  return rows == 2 ? "x, y" : "x, y, z";
}

void residualRow(std::ostream& out, const std::string& label, const ResidualStats& s,
                 const std::vector<int>& lines) {
  out << "residual |e| " << std::left << std::setw(22) << label + ":" << std::right << "rms "
      << um(s.rms) << ", max " << um(s.max) << lineText(lines, s.maxIndex) << "; per axis rms";
  for (Eigen::Index r = 0; r < s.rowRms.size(); ++r)
    out << " " << significant(s.rowRms(r) * 1e3, 4);
  out << " µm, max";
  for (Eigen::Index r = 0; r < s.rowMax.size(); ++r)
    out << " " << significant(s.rowMax(r) * 1e3, 4);
  out << " µm\n";
}

void parameterTable(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info,
                    const ReportContext& context) {
  const FitStatistics& st = fit.statistics;
  std::size_t width = 9;
  for (const ParameterInfo& p : info) width = std::max(width, p.name.size());
  out << std::left << std::setw(static_cast<int>(width)) << "parameter" << std::right
      << std::setw(12) << "start" << std::setw(12) << "value" << std::setw(11) << "sigma"
      << "  unit\n";
  for (std::size_t j = 0; j < info.size(); ++j) {
    const auto index = static_cast<Eigen::Index>(j);
    const DisplayUnit unit = screenUnit(info[j], context.angleDisplay);
    out << std::left << std::setw(static_cast<int>(width)) << info[j].name << std::right
        << std::setw(12) << significant(fit.start(index) * unit.factor, 4) << std::setw(12)
        << significant(fit.parameters(index) * unit.factor, 4) << std::setw(11)
        << significant(st.standardDeviation(index) * unit.factor, 3) << "  " << unit.unit
        << (st.identifiable[j] ? "" : "  not identifiable")
        << (info[j].nuisance ? "  (instrument frame)" : "") << "\n";
  }
}

void curveTable(std::ostream& out, const std::vector<SampledCurve>& curves, AngleDisplay angles) {
  if (curves.empty()) return;
  out << "\nidentified curves (value ± sigma at positions in mm; reversal = negative - positive "
         "curve):\n";
  for (const SampledCurve& c : curves) {
    const DisplayUnit unit = screenUnit(c.curve.angle, angles);
    // Where the values are not determined but their differences are (a constant shared with
    // another component), the sigma of the shape is shown, relative to the first position.
    const bool absolute =
        std::all_of(c.std.begin(), c.std.end(), [](double s) { return std::isfinite(s); });
    const bool shape = !absolute && std::all_of(c.relativeStd.begin(), c.relativeStd.end(),
                                                [](double s) { return std::isfinite(s); });
    out << "  " << c.curve.component
        << (c.curve.direction == CurveDirection::Both
                ? std::string()
                : std::string(" ") + curveDirectionName(c.curve.direction))
        << " (" << unit.unit;
    if (shape) {
      out << "; its constant is not determined, sigma of the shape relative to "
          << significant(c.curve.positionsMm.front(), 6) << " mm";
    }
    out << "):";
    const std::vector<double>& sigma = shape ? c.relativeStd : c.std;
    for (std::size_t k = 0; k < c.values.size(); ++k) {
      out << (k == 0 ? " " : ", ") << significant(c.curve.positionsMm[k], 6) << ": "
          << significant(c.values[k] * unit.factor, 4) << " ± "
          << significant(sigma[k] * unit.factor, 2);
    }
    if (c.curve.direction == CurveDirection::Reversal) {
      out << "; mean " << significant(c.mean * unit.factor, 4) << " ± "
          << significant(c.meanStd * unit.factor, 2);
    }
    out << "\n";
  }
}

void correlations(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info) {
  // The strongest correlations among identifiable parameters: where the data barely separate.
  const FitStatistics& st = fit.statistics;
  std::vector<std::tuple<double, int, int>> pairs;
  for (Eigen::Index i = 0; i < st.correlation.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < st.correlation.cols(); ++j) {
      const double c = st.correlation(i, j);
      if (std::isfinite(c) && std::abs(c) >= 0.9) {
        pairs.emplace_back(std::abs(c), static_cast<int>(i), static_cast<int>(j));
      }
    }
  }
  std::sort(pairs.rbegin(), pairs.rend());
  if (pairs.empty()) return;
  out << "\nstrong correlations (|r| >= 0.9):\n";
  for (std::size_t k = 0; k < std::min<std::size_t>(pairs.size(), 10); ++k) {
    const auto& [magnitude, i, j] = pairs[k];
    out << "  " << info[static_cast<std::size_t>(i)].name << " / "
        << info[static_cast<std::size_t>(j)].name << ": " << significant(st.correlation(i, j), 4)
        << "\n";
  }
}

}  // namespace

void writeMissingSummary(std::ostream& out, const FitResult& fit,
                         const std::vector<ParameterInfo>& info, const ReportContext& context) {
  const FitStatistics& st = fit.statistics;
  // Per component (template key) in template order: parameters in all, not identifiable.
  std::vector<std::string> order;
  std::map<std::string, std::pair<int, int>> counts;
  for (std::size_t j = 0; j < info.size(); ++j) {
    const std::string& key = info[j].keyPath;
    if (!counts.count(key)) order.push_back(key);
    auto& [total, missing] = counts[key];
    ++total;
    missing += st.identifiable[j] ? 0 : 1;
  }
  out << st.parameterCount - st.rank << " independent combinations of " << st.parameterCount
      << " parameters are not identifiable (rank " << st.rank << "); per component:\n";
  for (const std::string& key : order) {
    const auto& [total, missing] = counts[key];
    if (missing == 0) continue;
    out << "  " << key << ": " << missing << " of " << total << " not identifiable\n";
  }
  if (context.coverage) {
    const DataCoverage& c = *context.coverage;
    out << "the data: " << c.points << " point" << (c.points == 1 ? "" : "s");
    for (int axis = 0; axis < 3; ++axis) {
      const auto& span = c.spanMm[static_cast<std::size_t>(axis)];
      out << (axis == 0 ? ", " : "; ") << "XYZ"[axis] << " " << significant(span[0], 6) << ".."
          << significant(span[1], 6) << " mm";
      if (const auto& travel = c.travelMm[static_cast<std::size_t>(axis)]) {
        out << " of " << significant((*travel)[0], 6) << ".." << significant((*travel)[1], 6);
      }
    }
    out << "; " << c.toolsMm.size() << " tool offset" << (c.toolsMm.size() == 1 ? "" : "s") << "\n";
    out << "to identify more: measure over the whole travel of every axis with an identified "
           "component, with at least two tool lengths and a lateral tool offset (angular errors "
           "act through the tool's lever arms), and at least as many points as parameters / 3\n";
  }
}

void writeSummary(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info,
                  const ReportContext& context) {
  const FitStatistics& st = fit.statistics;
  out << "calibration of " << context.templateFile << " from " << context.measurementFile << " ("
      << context.lines.size() << " points, method " << methodName(context.method) << ", loss "
      << lossName(context.loss) << ")\n";
  out << (fit.converged ? "converged" : "NOT converged") << " after " << fit.iterations
      << " iterations: " << fit.termination << "\n\n";
  parameterTable(out, fit, info, context);

  const int rows = static_cast<int>(fit.after.rowRms.size());
  out << "\nresiduals (|e| and per axis " << axisNames(rows) << "):\n";
  residualRow(out, "before", fit.before, context.lines);
  residualRow(out, "after", fit.after, context.lines);
  if (context.validation) {
    const ValidationResult& v = *context.validation;
    const std::string label = v.kind == ValidationKind::File
                                  ? "held out (" + v.file + ")"
                                  : "held out (" + std::to_string(v.folds) + "-fold)";
    residualRow(out, label, v.stats, v.lines);
  }
  out << "s0 (scatter per weighted row) " << um(std::sqrt(st.varianceFactor)) << ", " << st.dof
      << " degrees of freedom\n";
  out << "rank " << st.rank << " of " << st.parameterCount << " (relative tolerance "
      << significant(context.rankTolerance, 3) << "), condition number "
      << significant(st.conditionNumber, 3);
  if (st.rank < st.parameterCount) {
    out << " (full: "
        << (std::isfinite(st.fullConditionNumber) ? significant(st.fullConditionNumber, 3)
                                                  : std::string("infinite"))
        << ")";
  }
  out << "\nidentifiable: projection onto the null space < "
      << significant(st.identifiabilityThreshold, 3)
      << "; what the data cannot see keeps the start values (minimum-norm change)\n";
  if (context.prediction) {
    const PredictionSummary& p = *context.prediction;
    out << "prediction uncertainty at the " << p.points
        << " measured points: U = k sigma of the "
           "predicted error, k = "
        << significant(kCoverageFactor, 2) << " (the compensated position has the same): ";
    if (p.undetermined < p.points) {
      out << "rms " << um(kCoverageFactor * p.rmsStdMm) << ", max "
          << um(kCoverageFactor * p.maxStdMm) << lineText(context.lines, p.maxIndex);
    }
    if (p.undetermined > 0) out << "; " << p.undetermined << " points not determined by the data";
    out << "\n";
  }
  curveTable(out, context.curves, context.angleDisplay);
  correlations(out, fit, info);
  if (!st.unidentifiable.empty()) {
    out << "\nnot identifiable with these data:\n";
    const std::size_t listed = std::min(st.unidentifiable.size(), kListedCombinations);
    for (std::size_t c = 0; c < listed; ++c) {
      const Combination& combination = st.unidentifiable[c];
      out << "  - " << combination.description << ";\n    in physical units: "
          << physicalDescription(combination, info, true, context.angleDisplay) << "\n";
    }
    if (listed < st.unidentifiable.size()) {
      out << "  ... and " << st.unidentifiable.size() - listed
          << " more (all in the report JSON); in short:\n";
      writeMissingSummary(out, fit, info, context);
    }
  }
  if (context.coverage && !context.coverage->toolsMm.empty()) {
    out << "\ntools measured (mm):";
    for (const Eigen::Vector3d& t : context.coverage->toolsMm) {
      out << " (" << significant(t.x(), 6) << ", " << significant(t.y(), 6) << ", "
          << significant(t.z(), 6) << ")";
    }
    out << "\n";
  }
}

}  // namespace volcomp::calibration
