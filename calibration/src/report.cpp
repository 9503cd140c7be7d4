#include "volcomp/calibration/report.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace volcomp::calibration {
namespace {

using Json = nlohmann::json;

// JSON has no infinity; an infinite condition number is written as null.
Json finiteOrNull(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json stats(const ResidualStats& s, const ReportContext& context) {
  Json out{{"rms_mm", s.rms}, {"max_mm", s.max}};
  if (s.maxIndex >= 0 && static_cast<std::size_t>(s.maxIndex) < context.lines.size()) {
    out["max_line"] = context.lines[static_cast<std::size_t>(s.maxIndex)];
  }
  return out;
}

std::string lineOf(const ResidualStats& s, const ReportContext& context) {
  if (s.maxIndex >= 0 && static_cast<std::size_t>(s.maxIndex) < context.lines.size()) {
    return " (line " + std::to_string(context.lines[static_cast<std::size_t>(s.maxIndex)]) + ")";
  }
  return {};
}

}  // namespace

nlohmann::json reportJson(const FitResult& fit, const std::vector<ParameterInfo>& info,
                          const ReportContext& context) {
  const FitStatistics& st = fit.statistics;
  Json parameters = Json::array();
  for (std::size_t j = 0; j < info.size(); ++j) {
    const auto index = static_cast<Eigen::Index>(j);
    parameters.push_back({{"name", info[j].name},
                          {"key", info[j].keyPath},
                          {"unit", info[j].unit},
                          {"value", fit.parameters(index) * info[j].toDisplay},
                          {"std", st.standardDeviation(index) * info[j].toDisplay},
                          {"start", fit.start(index) * info[j].toDisplay},
                          {"identifiable", static_cast<bool>(st.identifiable[j])},
                          {"nuisance", info[j].nuisance}});
  }
  Json correlation = Json::array();
  for (Eigen::Index i = 0; i < st.correlation.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index j = 0; j < st.correlation.cols(); ++j) row.push_back(st.correlation(i, j));
    correlation.push_back(row);
  }
  Json singular = Json::array();
  for (Eigen::Index i = 0; i < st.singularValues.size(); ++i)
    singular.push_back(st.singularValues(i));
  Json combinations = Json::array();
  for (const Combination& c : st.unidentifiable) {
    Json names = Json::array(), coefficients = Json::array();
    for (const auto& [index, coefficient] : c.terms) {
      names.push_back(info[static_cast<std::size_t>(index)].name);
      coefficients.push_back(coefficient);
    }
    combinations.push_back({{"parameters", names},
                            {"coefficients", coefficients},
                            {"relative_singular_value", c.relativeSingularValue},
                            {"description", c.description}});
  }
  return Json{
      {"format", "volcomp-calibration-report/1"},
      {"template", context.templateFile},
      {"measurements", context.measurementFile},
      {"method", context.method},
      {"loss", context.loss},
      {"points", context.lines.size()},
      {"converged", fit.converged},
      {"iterations", fit.iterations},
      {"termination", fit.termination},
      {"parameters", parameters},
      {"correlation", correlation},
      {"residuals", {{"before", stats(fit.before, context)}, {"after", stats(fit.after, context)}}},
      {"rank", st.rank},
      {"parameter_count", st.parameterCount},
      {"rank_tolerance", context.rankTolerance},
      {"condition_number", finiteOrNull(st.conditionNumber)},
      {"full_condition_number", finiteOrNull(st.fullConditionNumber)},
      {"singular_values", singular},
      {"rows", st.rowCount},
      {"dof", st.dof},
      {"s0_mm", std::sqrt(st.varianceFactor)},
      {"unidentifiable", combinations}};
}

void writeSummary(std::ostream& out, const FitResult& fit, const std::vector<ParameterInfo>& info,
                  const ReportContext& context) {
  const FitStatistics& st = fit.statistics;
  const std::ios::fmtflags flags = out.flags();
  const std::streamsize precision = out.precision();
  out << "calibration of " << context.templateFile << " from " << context.measurementFile << " ("
      << context.lines.size() << " points, method " << context.method << ", loss " << context.loss
      << ")\n";
  out << (fit.converged ? "converged" : "NOT converged") << " after " << fit.iterations
      << " iterations: " << fit.termination << "\n\n";

  std::size_t width = 9;
  for (const ParameterInfo& p : info) width = std::max(width, p.name.size());
  out << std::left << std::setw(static_cast<int>(width)) << "parameter" << std::right
      << std::setw(16) << "value" << std::setw(14) << "sigma"
      << "  unit\n";
  for (std::size_t j = 0; j < info.size(); ++j) {
    const auto index = static_cast<Eigen::Index>(j);
    out << std::left << std::setw(static_cast<int>(width)) << info[j].name << std::right
        << std::setw(16) << std::setprecision(6) << std::defaultfloat
        << fit.parameters(index) * info[j].toDisplay << std::setw(14) << std::setprecision(3)
        << st.standardDeviation(index) * info[j].toDisplay << "  " << info[j].unit
        << (st.identifiable[j] ? "" : "  (not identifiable)")
        << (info[j].nuisance ? "  (instrument frame)" : "") << "\n";
  }
  out << std::setprecision(4) << "\nresidual |e| before: rms " << fit.before.rms * 1000.0
      << " um, max " << fit.before.max * 1000.0 << " um" << lineOf(fit.before, context) << "\n";
  out << "residual |e| after:  rms " << fit.after.rms * 1000.0 << " um, max "
      << fit.after.max * 1000.0 << " um" << lineOf(fit.after, context) << "\n";
  out << "s0 (scatter per weighted row) " << std::sqrt(st.varianceFactor) * 1000.0 << " um, "
      << st.dof << " degrees of freedom\n";
  out << "rank " << st.rank << " of " << st.parameterCount << " (relative tolerance "
      << context.rankTolerance << "), condition number " << st.conditionNumber;
  if (st.rank < st.parameterCount) out << " (full: " << st.fullConditionNumber << ")";
  out << "\n";

  // The strongest correlations among identifiable parameters: where the data barely separate.
  std::vector<std::tuple<double, int, int>> pairs;
  for (Eigen::Index i = 0; i < st.correlation.rows(); ++i) {
    for (Eigen::Index j = i + 1; j < st.correlation.cols(); ++j) {
      if (!st.identifiable[static_cast<std::size_t>(i)] ||
          !st.identifiable[static_cast<std::size_t>(j)]) {
        continue;
      }
      const double c = st.correlation(i, j);
      if (std::abs(c) >= 0.9)
        pairs.emplace_back(std::abs(c), static_cast<int>(i), static_cast<int>(j));
    }
  }
  std::sort(pairs.rbegin(), pairs.rend());
  if (!pairs.empty()) {
    out << "\nstrong correlations (|r| >= 0.9):\n";
    for (std::size_t k = 0; k < std::min<std::size_t>(pairs.size(), 10); ++k) {
      const auto& [magnitude, i, j] = pairs[k];
      out << "  " << info[static_cast<std::size_t>(i)].name << " / "
          << info[static_cast<std::size_t>(j)].name << ": " << std::setprecision(4)
          << st.correlation(i, j) << "\n";
    }
  }
  if (!st.unidentifiable.empty()) {
    out << "\nnot identifiable with these data:\n";
    for (const Combination& c : st.unidentifiable) out << "  - " << c.description << "\n";
  }
  out.flags(flags);
  out.precision(precision);
}

}  // namespace volcomp::calibration
