// The top of the report: header, the summary a manager reads, and the footer.

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <variant>

#include "sections.hpp"
#include "volcomp/report/assets.hpp"

namespace volcomp::report::detail {
namespace {

std::string dateText(std::time_t date, const char* format) {
  std::tm local{};
  localtime_r(&date, &local);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, format, &local);
  return buffer;
}

std::string um(double value) {
  return fixed(value, value < 10.0 ? 2 : 1) + "&#8239;µm";
}

std::string card(const std::string& label, const std::string& value, const std::string& detail,
                 const std::string& cssClass = {}) {
  return "<div class=\"card" + (cssClass.empty() ? "" : " " + cssClass) +
         "\"><div class=\"label\">" + escape(label) + "</div><div class=\"value\">" + value +
         "</div><div class=\"detail\">" + detail + "</div></div>\n";
}

std::string topologyText(const Context& context) {
  if (context.model == nullptr) return "D-H chain";
  return context.model->spec().topology;
}

const ComponentView* largestComponent(const std::vector<ComponentView>& views) {
  const ComponentView* best = nullptr;
  for (const ComponentView& v : views) {
    if (v.angular) continue;
    if (best == nullptr || v.peakAbs > best->peakAbs) best = &v;
  }
  return best;
}

std::optional<double> reduction(const ErrorStats& stats) {
  if (!stats.rmsBefore || !stats.rmsAfter || *stats.rmsBefore <= 0.0) return std::nullopt;
  return 100.0 * (1.0 - *stats.rmsAfter / *stats.rmsBefore);
}

const IsoFigure* figure(const IsoAxis& axis, const std::string& symbol) {
  for (const IsoFigure& f : axis.figures) {
    if (f.symbol == symbol) return &f;
  }
  return nullptr;
}

// One sentence per input, in the order of the sections.
std::string leadText(const Context& context) {
  std::string text;
  if (context.model != nullptr && context.volumeStats) {
    const VolumeStatistics& s = *context.volumeStats;
    text += "The geometric error model of " + escape(machineName(context)) +
            " predicts a tool-tip error of up to <b>" + um(s.maxUm) +
            "</b> over the working volume of " + volumeText(context) + " (RMS " + um(s.rmsUm) +
            " over " + std::to_string(s.points) + " points), largest at X " +
            fixed(s.maxAtMm.x(), 0) + ", Y " + fixed(s.maxAtMm.y(), 0) + ", Z " +
            fixed(s.maxAtMm.z(), 0) + " mm.";
    const std::vector<ComponentView> views = componentViews(*context.model, context.volume, 41);
    if (const ComponentView* largest = largestComponent(views)) {
      text += " The largest single error is " + largest->name + " (" + largest->meaning +
              "), up to " + um(largest->peakAbs) + ".";
    }
  }
  if (const auto& run = context.inputs.run) {
    if (const auto r = reduction(run->total)) {
      text += " In the compensation run, live compensation reduced the RMS tool-tip error from " +
              um(*run->total.rmsBefore) + " to <b>" + um(*run->total.rmsAfter) + "</b> (" +
              fixed(*r, 0) + "&#8239;% less)";
      if (run->limiterViolations) {
        text += ", with " + std::to_string(*run->limiterViolations) + " limiter violation" +
                (*run->limiterViolations == 1 ? "" : "s");
        if (run->writes) text += " in " + std::to_string(*run->writes) + " writes";
      }
      text += ".";
    }
  }
  if (const auto& cal = context.inputs.calibration) {
    text += " The calibration";
    if (cal->points) text += " from " + std::to_string(*cal->points) + " measured points";
    if (cal->rank && cal->parameterCount) {
      text += " determined " + std::to_string(*cal->rank) + " of " +
              std::to_string(*cal->parameterCount) + " parameters";
    }
    if (cal->before.rmsMm && cal->after.rmsMm) {
      text += "; the residual error fell from " + um(*cal->before.rmsMm * kUmPerMm) + " to " +
              um(*cal->after.rmsMm * kUmPerMm) + " RMS";
    }
    text += ".";
    if (!cal->unidentifiable.empty()) {
      text += " " + std::to_string(cal->unidentifiable.size()) +
              " combination(s) of parameters cannot be separated with these measurements.";
    }
  }
  for (const IsoAxis& axis : context.inputs.iso) {
    const IsoFigure* a = figure(axis, "A");
    const IsoFigure* r = figure(axis, "R");
    const IsoFigure* b = figure(axis, "B");
    if (a == nullptr) continue;
    const std::string name = axis.axis ? axisName(*axis.axis) : "";
    text += " ISO 230-2 positioning of " + name + ": accuracy A = <b>" + um(a->valueUm) + "</b>";
    if (r != nullptr) text += ", repeatability R = " + um(r->valueUm);
    if (b != nullptr) text += ", reversal B = " + um(b->valueUm);
    text += ".";
  }
  return text;
}

std::string cards(const Context& context) {
  std::string out;
  if (context.volumeStats) {
    const VolumeStatistics& s = *context.volumeStats;
    out += card("Volumetric error", fixed(s.maxUm, 1) + "<small> µm max</small>",
                "RMS " + um(s.rmsUm) + " · the model, uncompensated");
  }
  if (const auto& run = context.inputs.run) {
    if (const auto r = reduction(run->total)) {
      const std::int64_t violations = run->limiterViolations.value_or(0);
      const std::string cssClass = violations > 0 ? "bad" : (*r >= 50.0 ? "good" : "warn");
      out += card("Live compensation", fixed(*run->total.rmsAfter, 2) + "<small> µm RMS</small>",
                  "from " + um(*run->total.rmsBefore) + " · " + fixed(*r, 0) + "&#8239;% less · " +
                      std::to_string(violations) + " limiter violations",
                  cssClass);
    }
  }
  if (const auto& cal = context.inputs.calibration) {
    if (cal->after.rmsMm) {
      std::string detail;
      if (cal->before.rmsMm) detail += "from " + um(*cal->before.rmsMm * kUmPerMm);
      if (cal->rank && cal->parameterCount) {
        detail += (detail.empty() ? "" : " · ") + std::string("rank ") +
                  std::to_string(*cal->rank) + " of " + std::to_string(*cal->parameterCount);
      }
      const bool full = !cal->rank || !cal->parameterCount || *cal->rank == *cal->parameterCount;
      out += card("Calibration residual",
                  fixed(*cal->after.rmsMm * kUmPerMm, 2) + "<small> µm RMS</small>", detail,
                  full ? "" : "warn");
    }
  }
  for (const IsoAxis& axis : context.inputs.iso) {
    const IsoFigure* a = figure(axis, "A");
    if (a == nullptr) continue;
    std::string detail;
    for (const char* symbol : {"R", "B", "E", "M"}) {
      if (const IsoFigure* f = figure(axis, symbol)) {
        detail += (detail.empty() ? "" : " · ") + std::string(symbol) + " " + um(f->valueUm);
      }
    }
    const std::string name = axis.axis ? axisName(*axis.axis) : "";
    out += card("ISO 230-2 accuracy " + name, fixed(a->valueUm, 1) + "<small> µm</small>", detail);
  }
  return out.empty() ? out : "<div class=\"cards\">\n" + out + "</div>\n";
}

std::string facts(const Context& context) {
  std::string out = "<dl class=\"facts\">\n";
  const auto fact = [&](const std::string& term, const std::string& html) {
    out += "<dt>" + escape(term) + "</dt><dd>" + html + "</dd>\n";
  };
  fact("Machine", escape(machineName(context)));
  fact("Model", "<code>" + escape(context.inputs.model.file) + "</code> (" +
                    escape(topologyText(context)) + ")");
  if (context.model != nullptr) {
    fact("Working volume", volumeText(context));
    const Eigen::Vector3d& tool = context.model->toolMm();
    fact("Tool offset",
         fixed(tool.x(), 1) + ", " + fixed(tool.y(), 1) + ", " + fixed(tool.z(), 1) + " mm");
  }
  std::string inputs;
  for (const InputFile& file : context.inputs.files) {
    if (file.role == "model") continue;
    inputs += (inputs.empty() ? "" : ", ") + escape(file.role);
  }
  fact("Also from", inputs.empty() ? "<span class=\"absent\">the model only</span>" : inputs);
  fact("Report", dateText(context.options.date, "%Y-%m-%d %H:%M") + ", volcomp " +
                     escape(context.options.volcompVersion));
  return out + "</dl>\n";
}

}  // namespace

std::string machineName(const Context& context) {
  if (!context.options.machine.empty()) return context.options.machine;
  if (const auto* spec = std::get_if<model::MachineModelSpec>(&context.inputs.model.spec)) {
    if (!spec->name.empty()) return spec->name;
  }
  return std::filesystem::path(context.inputs.model.file).stem().string();
}

std::string volumeText(const Context& context) {
  std::string out;
  bool allTravel = true;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto [lo, hi] = context.volume.rangeMm[k];
    out += (k == 0 ? "" : " × ") + fixed(hi - lo, 0);
    allTravel = allTravel && context.volume.fromTravel[k];
  }
  return out + " mm" + (allTravel ? "" : " (partly from the tables: the model gives no travel)");
}

std::string headerHtml(const Context& context) {
  return "<header class=\"report-header\"><p class=\"kicker\">volcomp · " +
         escape(context.options.title) + "</p><h1>" + escape(machineName(context)) +
         "</h1><p class=\"meta\"><span>" + escape(topologyText(context)) + "</span><span>" +
         dateText(context.options.date, "%Y-%m-%d %H:%M") + "</span><span>volcomp " +
         escape(context.options.volcompVersion) + "</span></p></header>\n";
}

std::string summaryHtml(const Context& context) {
  return "<section class=\"summary\" id=\"summary\" aria-label=\"Summary\">\n" +
         paragraph(leadText(context), "lead") + cards(context) + facts(context) + "</section>\n";
}

std::string footerHtml(const Context& context) {
  return "<footer>Written by volcomp " + escape(context.options.volcompVersion) + " on " +
         dateText(context.options.date, "%Y-%m-%d %H:%M %Z") +
         ". Errors E = actual − nominal tool-tip position in the workpiece frame (ISO 230-1 "
         "names). Charts drawn with Vega " +
         escape(std::string(vegaVersion())) +
         " (BSD-3-Clause, included in this file with its licence).</footer>\n";
}

}  // namespace volcomp::report::detail
