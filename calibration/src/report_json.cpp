// The JSON report (volcomp-calibration-report/1), structure in docs/calibration.md.

#include <cmath>

#include "volcomp/calibration/report.hpp"

namespace volcomp::calibration {
namespace {

using Json = nlohmann::json;

// JSON has no infinity or NaN: a value that does not exist (an infinite condition number, the
// sigma of a parameter the data do not determine) is written as null.
Json finiteOrNull(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json vector3(const Eigen::Vector3d& v) {
  return Json::array({finiteOrNull(v.x()), finiteOrNull(v.y()), finiteOrNull(v.z())});
}

Json lineAt(const std::vector<int>& lines, int index) {
  if (index >= 0 && static_cast<std::size_t>(index) < lines.size()) {
    return lines[static_cast<std::size_t>(index)];
  }
  return nullptr;
}

Json stats(const ResidualStats& s, const std::vector<int>& lines) {
  Json out{{"rms_mm", s.rms}, {"max_mm", s.max}};
  if (const Json line = lineAt(lines, s.maxIndex); !line.is_null()) out["max_line"] = line;
  Json rms = Json::array(), max = Json::array(), maxLine = Json::array();
  for (Eigen::Index r = 0; r < s.rowRms.size(); ++r) {
    rms.push_back(s.rowRms(r));
    max.push_back(s.rowMax(r));
    maxLine.push_back(lineAt(lines, s.rowMaxIndex[static_cast<std::size_t>(r)]));
  }
  out["axes"] = {{"rms_mm", rms}, {"max_mm", max}, {"max_line", maxLine}};
  return out;
}

Json prediction(const PointPrediction& p) {
  Json out{{"position_mm", vector3(p.qMm)},
           {"tool_mm", vector3(p.toolMm)},
           {"error_mm", vector3(p.errorMm)},
           {"std_mm", vector3(p.stdMm)},
           {"expanded_mm", vector3(kCoverageFactor * p.stdMm)},
           {"determined", p.determined}};
  if (p.line > 0) out["line"] = p.line;
  return out;
}

Json curveJson(const SampledCurve& c) {
  Json values = Json::array(), stds = Json::array(), relative = Json::array();
  for (std::size_t k = 0; k < c.values.size(); ++k) {
    values.push_back(c.values[k] * c.curve.toDisplay);
    stds.push_back(finiteOrNull(c.std[k] * c.curve.toDisplay));
    relative.push_back(finiteOrNull(c.relativeStd[k] * c.curve.toDisplay));
  }
  Json out{{"component", c.curve.component},
           {"direction", c.curve.direction == CurveDirection::Both
                             ? Json(nullptr)
                             : Json(curveDirectionName(c.curve.direction))},
           {"unit", c.curve.unit},
           {"positions_mm", c.curve.positionsMm},
           {"values", values},
           {"std", stds},
           {"std_relative_to_first", relative}};
  if (c.curve.direction == CurveDirection::Reversal) {
    out["mean"] = c.mean * c.curve.toDisplay;
    out["mean_std"] = finiteOrNull(c.meanStd * c.curve.toDisplay);
  }
  return out;
}

}  // namespace

const char* validationKindName(ValidationKind kind) noexcept {
  return kind == ValidationKind::KFold ? "k-fold" : "file";
}

const char* reportKindName(ReportKind kind) noexcept {
  return kind == ReportKind::Planar2Dof ? "planar2dof" : "machine";
}

const char* methodName(Method method) noexcept {
  return method == Method::LevenbergMarquardt ? "levenberg-marquardt" : "linear";
}

const char* lossName(RobustLoss loss) noexcept {
  switch (loss) {
    case RobustLoss::Huber:
      return "huber";
    case RobustLoss::Cauchy:
      return "cauchy";
    case RobustLoss::None:
      break;
  }
  return "none";
}

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
                          {"std", finiteOrNull(st.standardDeviation(index) * info[j].toDisplay)},
                          {"start", fit.start(index) * info[j].toDisplay},
                          {"identifiable", static_cast<bool>(st.identifiable[j])},
                          {"null_space_projection", st.nullSpaceProjection(index)},
                          {"nuisance", info[j].nuisance}});
  }
  Json correlation = Json::array();
  for (Eigen::Index i = 0; i < st.correlation.rows(); ++i) {
    Json row = Json::array();
    for (Eigen::Index j = 0; j < st.correlation.cols(); ++j) {
      row.push_back(finiteOrNull(st.correlation(i, j)));
    }
    correlation.push_back(row);
  }
  Json singular = Json::array();
  for (Eigen::Index i = 0; i < st.singularValues.size(); ++i) {
    singular.push_back(st.singularValues(i));
  }
  Json combinations = Json::array();
  for (const Combination& c : st.unidentifiable) {
    Json names = Json::array(), coefficients = Json::array(), steps = Json::array(),
         units = Json::array();
    const double pivotStep = 1.0 / info[static_cast<std::size_t>(c.pivot)].toDisplay;
    for (std::size_t t = 0; t < c.terms.size(); ++t) {
      const ParameterInfo& p = info[static_cast<std::size_t>(c.terms[t].first)];
      names.push_back(p.name);
      coefficients.push_back(c.terms[t].second);
      steps.push_back(c.rawTerms[t].second * pivotStep * p.toDisplay);
      units.push_back(p.unit);
    }
    combinations.push_back(
        {{"parameters", names},
         {"coefficients", coefficients},
         {"relative_singular_value", c.relativeSingularValue},
         {"description", c.description},
         {"physical",
          {{"pivot", info[static_cast<std::size_t>(c.pivot)].name},
           {"steps", steps},
           {"units", units},
           {"residual_change_mm", c.residualChangePerPivotUnit * pivotStep},
           {"description", physicalDescription(c, info, false, context.angleDisplay)}}}});
  }
  Json residuals{{"before", stats(fit.before, context.lines)},
                 {"after", stats(fit.after, context.lines)}};
  if (context.validation) {
    const ValidationResult& v = *context.validation;
    Json validation = stats(v.stats, v.lines);
    validation["kind"] = validationKindName(v.kind);
    validation["points"] = v.lines.size();
    if (v.kind == ValidationKind::File) validation["file"] = v.file;
    if (v.kind == ValidationKind::KFold) {
      validation["folds"] = v.folds;
      validation["fold_rms_mm"] = v.foldRmsMm;
      validation["fold_rank"] = v.foldRank;
    }
    residuals["validation"] = validation;
  }
  Json report{
      {"format", "volcomp-calibration-report/1"},
      {"kind", reportKindName(context.kind)},
      {"volcomp_version", context.volcompVersion},
      {"date", context.date},
      {"template", context.templateFile},
      {"measurements", context.measurementFile},
      {"method", methodName(context.method)},
      {"loss", lossName(context.loss)},
      {"points", context.lines.size()},
      {"converged", fit.converged},
      {"iterations", fit.iterations},
      {"termination", fit.termination},
      {"parameters", parameters},
      {"correlation", correlation},
      {"residuals", residuals},
      {"rank", st.rank},
      {"parameter_count", st.parameterCount},
      {"rank_tolerance", context.rankTolerance},
      {"condition_number", finiteOrNull(st.conditionNumber)},
      {"full_condition_number", finiteOrNull(st.fullConditionNumber)},
      {"singular_values", singular},
      {"rows", st.rowCount},
      {"dof", st.dof},
      {"s0_mm", std::sqrt(st.varianceFactor)},
      {"identifiability",
       {{"rule",
         "a parameter is identifiable when the projection of its column-scaled unit vector onto "
         "the numerical null space (right singular vectors with s_i <= rank_tolerance * s_1) is "
         "below projection_threshold; otherwise it has no std and is named in a combination"},
        {"projection_threshold", st.identifiabilityThreshold},
        {"rank_tolerance", context.rankTolerance},
        {"policy",
         "along directions the data cannot see, the solution is the minimum-norm change from the "
         "start values in column-scaled units (each parameter in units of its sensitivity)"}}},
      {"unidentifiable", combinations}};
  if (context.prediction) {
    const PredictionSummary& p = *context.prediction;
    Json summary{{"coverage_factor", kCoverageFactor},
                 {"where", "measured points"},
                 {"points", p.points},
                 {"undetermined", p.undetermined},
                 {"rms_std_mm", p.rmsStdMm},
                 {"max_std_mm", p.maxStdMm},
                 {"max_axis_std_mm", vector3(p.maxAxisStdMm)},
                 {"rms_expanded_mm", kCoverageFactor * p.rmsStdMm},
                 {"max_expanded_mm", kCoverageFactor * p.maxStdMm},
                 {"max_line", lineAt(context.lines, p.maxIndex)}};
    Json at = Json::array();
    for (const PointPrediction& point : context.predictedAt) at.push_back(prediction(point));
    report["prediction"] = {{"measured", summary}, {"at", at}};
  }
  if (!context.curves.empty()) {
    Json curves = Json::array();
    Json reversal = Json::array();
    for (const SampledCurve& c : context.curves) {
      (c.curve.direction == CurveDirection::Reversal ? reversal : curves).push_back(curveJson(c));
    }
    report["curves"] = curves;
    if (!reversal.empty()) report["reversal"] = reversal;
  }
  if (context.coverage) {
    Json tools = Json::array();
    for (const Eigen::Vector3d& t : context.coverage->toolsMm) tools.push_back(vector3(t));
    report["tools_mm"] = tools;
  }
  return report;
}

}  // namespace volcomp::calibration
