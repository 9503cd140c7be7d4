// Reader of ISO 230-2 evaluations (`volcomp iso230-2 --json`, volcomp-iso230-2/1: one axis, all
// lengths in the units the document states, mm by the format).

#include <algorithm>
#include <cmath>

#include "json_fields.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/report/inputs.hpp"

namespace volcomp::report {
namespace {

using detail::Fields;
using nlohmann::json;

// The axis figures in the order of ISO 230-2:2014 and their keys in `axis_figures`.
struct FigureKey {
  const char* key;
  const char* symbol;
  const char* meaning;
};
constexpr FigureKey kFigures[] = {
    {"reversal", "B", "reversal value of the axis, max |B_i|"},
    {"mean_reversal", "B̄", "mean reversal value"},
    {"repeatability_positive", "R↑", "unidirectional repeatability, positive direction"},
    {"repeatability_negative", "R↓", "unidirectional repeatability, negative direction"},
    {"repeatability_bidirectional", "R", "bidirectional repeatability"},
    {"systematic_positive", "E↑", "unidirectional systematic positional deviation, positive"},
    {"systematic_negative", "E↓", "unidirectional systematic positional deviation, negative"},
    {"systematic_bidirectional", "E", "bidirectional systematic positional deviation"},
    {"mean_bidirectional_range", "M", "range of the mean bidirectional positional deviation"},
    {"accuracy_positive", "A↑", "unidirectional accuracy of positioning, positive direction"},
    {"accuracy_negative", "A↓", "unidirectional accuracy of positioning, negative direction"},
    {"accuracy_bidirectional", "A", "bidirectional accuracy of positioning"},
};

// Length units a document may state, in mm.
double unitToMm(const std::string& unit, const std::string& file, const std::string& key) {
  if (unit.empty() || unit == "mm") return 1.0;
  if (unit == "um" || unit == "µm") return 1e-3;
  if (unit == "nm") return 1e-6;
  if (unit == "m") return 1e3;
  if (unit == "in") return 25.4;
  throw config::ConfigError(file, key, "expected a length unit (mm, um, nm, m, in), got " + unit);
}

IsoTarget readTarget(Fields& t, double positionToMm, double deviationToUm) {
  const auto um = [&](const char* key) -> std::optional<double> {
    const auto value = t.number(key);
    if (!value) return std::nullopt;
    return *value * deviationToUm;
  };
  IsoTarget target;
  target.positionMm = t.number("position").value_or(0.0) * positionToMm;
  target.meanUp = um("mean_positive");
  target.meanDown = um("mean_negative");
  target.mean = um("mean_bidirectional");
  target.reversal = um("reversal");
  target.sUp = um("s_positive");
  target.sDown = um("s_negative");
  target.repeatUp = um("repeatability_positive");
  target.repeatDown = um("repeatability_negative");
  target.repeat = um("repeatability_bidirectional");
  for (double v : t.numbers("deviations_positive")) target.runsUp.push_back(v * deviationToUm);
  for (double v : t.numbers("deviations_negative")) target.runsDown.push_back(v * deviationToUm);
  return target;
}

}  // namespace

IsoAxis readIsoAxis(const json& document, const std::string& file, Notes& notes) {
  if (!document.is_object()) throw config::ConfigError(file, "", "expected a JSON object");
  Fields top(document, file, "", notes);
  detail::checkFormat(top, "volcomp-iso230-2",
                      "an ISO 230-2 evaluation (volcomp-iso230-2/1, written by volcomp iso230-2 "
                      "--json)");
  IsoAxis axis;
  axis.file = file;
  const std::string axisText = top.text("axis");
  axis.axis = model::axisFromName(axisText);
  if (!axisText.empty() && !axis.axis) {
    notes.push_back(file + ": " + top.path("axis") + ": expected X, Y or Z, got \"" + axisText +
                    "\"; not shown");
  }
  axis.source = top.text("source");
  axis.standard = top.text("standard");
  double positionToMm = 1.0, deviationToUm = 1e3;
  if (const json* units = top.object("units")) {
    Fields u(*units, file, "units", notes);
    positionToMm = unitToMm(u.text("position"), file, "units.position");
    deviationToUm = unitToMm(u.text("deviation"), file, "units.deviation") * 1e3;
  }
  if (const json* runs = top.array("runs_positive")) axis.runsUp = static_cast<int>(runs->size());
  if (const json* runs = top.array("runs_negative")) axis.runsDown = static_cast<int>(runs->size());
  if (const json* targets = top.array("targets")) {
    for (std::size_t i = 0; i < targets->size(); ++i) {
      Fields t((*targets)[i], file, "targets[" + std::to_string(i) + "]", notes);
      if (!t.number("position")) {
        notes.push_back(file + ": " + t.path("position") + ": missing; target not shown");
        continue;
      }
      axis.targets.push_back(readTarget(t, positionToMm, deviationToUm));
    }
  }
  std::sort(axis.targets.begin(), axis.targets.end(),
            [](const IsoTarget& a, const IsoTarget& b) { return a.positionMm < b.positionMm; });
  if (const json* figures = top.object("axis_figures")) {
    Fields f(*figures, file, "axis_figures", notes);
    for (const FigureKey& key : kFigures) {
      if (const auto value = f.number(key.key)) {
        axis.figures.push_back({key.symbol, key.meaning, *value * deviationToUm});
      }
    }
  }
  if (const json* warnings = top.array("warnings")) {
    for (const json& w : *warnings) {
      if (w.is_string()) axis.warnings.push_back(w.get<std::string>());
    }
  }
  if (axis.targets.empty()) notes.push_back(file + ": no targets; the axis is not shown");
  return axis;
}

IsoAxis loadIsoAxis(const std::string& path, Notes& notes) {
  return readIsoAxis(readJsonFile(path), path, notes);
}

}  // namespace volcomp::report
