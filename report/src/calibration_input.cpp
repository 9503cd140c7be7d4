// Reader of `volcomp calibrate --report` documents (volcomp-calibration-report/N).

#include <cmath>
#include <limits>

#include "json_fields.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {
namespace {

using detail::Fields;
using nlohmann::json;

ResidualSide readSide(const json* object, const std::string& file, const std::string& path,
                      Notes& notes) {
  ResidualSide side;
  if (object == nullptr) return side;
  Fields fields(*object, file, path, notes);
  side.rmsMm = fields.number("rms_mm");
  side.maxMm = fields.number("max_mm");
  if (const auto line = fields.integer("max_line")) side.maxLine = static_cast<int>(*line);
  // Whatever else a newer calibrate puts here (per-axis figures, ...), numbers one level deep.
  for (const auto& [key, value] : object->items()) {
    if (key == "rms_mm" || key == "max_mm" || key == "max_line") continue;
    if (value.is_number()) side.more.emplace_back(key, value.get<double>());
    if (value.is_object()) {
      for (const auto& [sub, inner] : value.items()) {
        if (inner.is_number()) side.more.emplace_back(key + "." + sub, inner.get<double>());
      }
    }
  }
  return side;
}

std::vector<CalibrationParameter> readParameters(Fields& top) {
  std::vector<CalibrationParameter> parameters;
  const json* list = top.array("parameters");
  if (list == nullptr) return parameters;
  for (std::size_t i = 0; i < list->size(); ++i) {
    Fields p((*list)[i], top.file(), top.path("parameters") + "[" + std::to_string(i) + "]",
             top.notes());
    CalibrationParameter parameter;
    parameter.name = p.text("name");
    if (parameter.name.empty()) parameter.name = "parameter " + std::to_string(i + 1);
    parameter.unit = p.text("unit");
    parameter.start = p.number("start");
    parameter.value = p.number("value");
    parameter.sigma = p.number("std");
    parameter.identifiable = p.boolean("identifiable");
    parameter.nuisance = p.boolean("nuisance").value_or(false);
    parameters.push_back(std::move(parameter));
  }
  return parameters;
}

// Row-major n x n; null entries (no correlation for a parameter without sigma) become NaN.
std::vector<double> readCorrelation(Fields& top, std::size_t n) {
  const json* rows = top.array("correlation");
  if (rows == nullptr || n == 0) return {};
  if (rows->size() != n) {
    top.notes().push_back(top.file() + ": correlation: " + std::to_string(rows->size()) +
                          " rows for " + std::to_string(n) + " parameters; not shown");
    return {};
  }
  std::vector<double> matrix;
  matrix.reserve(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    const json& row = (*rows)[i];
    if (!row.is_array() || row.size() != n) {
      top.notes().push_back(top.file() + ": correlation[" + std::to_string(i) + "]: expected " +
                            std::to_string(n) + " numbers; not shown");
      return {};
    }
    for (const json& value : row) {
      matrix.push_back(value.is_number() ? value.get<double>()
                                         : std::numeric_limits<double>::quiet_NaN());
    }
  }
  return matrix;
}

}  // namespace

CalibrationReport readCalibrationReport(const json& document, const std::string& file,
                                        Notes& notes) {
  if (!document.is_object()) throw config::ConfigError(file, "", "expected a JSON object");
  Fields top(document, file, "", notes);
  detail::checkFormat(top, "volcomp-calibration-report",
                      "a calibration report (volcomp-calibration-report/1, written by volcomp "
                      "calibrate --report)");
  CalibrationReport report;
  report.file = file;
  report.templateFile = top.text("template");
  report.measurementFile = top.text("measurements");
  report.method = top.text("method");
  report.loss = top.text("loss");
  report.termination = top.text("termination");
  report.converged = top.boolean("converged");
  const auto asInt = [](std::optional<std::int64_t> v) -> std::optional<int> {
    if (!v) return std::nullopt;
    return static_cast<int>(*v);
  };
  report.points = asInt(top.integer("points"));
  report.iterations = asInt(top.integer("iterations"));
  report.rank = asInt(top.integer("rank"));
  report.parameterCount = asInt(top.integer("parameter_count"));
  report.dof = asInt(top.integer("dof"));
  report.conditionNumber = top.number("condition_number");
  report.s0Mm = top.number("s0_mm");
  report.parameters = readParameters(top);
  report.correlation = readCorrelation(top, report.parameters.size());
  if (const json* residuals = top.object("residuals")) {
    Fields r(*residuals, file, "residuals", notes);
    report.before = readSide(r.object("before"), file, "residuals.before", notes);
    report.after = readSide(r.object("after"), file, "residuals.after", notes);
  }
  if (const json* combinations = top.array("unidentifiable")) {
    for (std::size_t i = 0; i < combinations->size(); ++i) {
      Fields c((*combinations)[i], file, "unidentifiable[" + std::to_string(i) + "]", notes);
      const std::string description = c.text("description");
      if (!description.empty()) report.unidentifiable.push_back(description);
    }
  }
  report.otherFields = top.unread();
  return report;
}

CalibrationReport loadCalibrationReport(const std::string& path, Notes& notes) {
  return readCalibrationReport(readJsonFile(path), path, notes);
}

}  // namespace volcomp::report
