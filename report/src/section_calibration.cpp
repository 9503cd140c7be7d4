// Section "Calibration": residuals before/after, the parameters with their standard deviations
// (laid out like Hanak, Zirn and Ruoff's table 2: starting value, optimised value, standard deviation),
// correlations, and what the measurements cannot separate.

#include <algorithm>
#include <cmath>
#include <tuple>

#include "charts.hpp"
#include "sections.hpp"

namespace volcomp::report::detail {
namespace {

std::string valueWithUnit(const std::string& value, const std::string& unit) {
  if (value == "–" || unit.empty()) return value;
  return value + "&#8239;" + escape(unit == "um" ? "µm" : unit == "urad" ? "µrad" : unit);
}

Table parameterTable(const CalibrationReport& report) {
  Table table({text("parameter"), numberHtml("starting value"), numberHtml("optimised value"),
               numberHtml("standard deviation s<sub>i</sub>"), text("")},
              "Parameters in the template's units; values rounded to the decimal place of their "
              "standard deviation (two significant digits).");
  for (const CalibrationParameter& p : report.parameters) {
    const double sigma = p.sigma.value_or(std::nan(""));
    const auto [value, s] =
        p.value ? withUncertainty(*p.value, sigma) : std::pair<std::string, std::string>{"–", "–"};
    // The start value with as many decimals as the optimised one (a start of 0 as "0").
    const auto point = value.find('.');
    const int decimals =
        point == std::string::npos ? 0 : static_cast<int>(value.size() - point - 1);
    const std::string start = !p.start ? "–" : *p.start == 0.0 ? "0" : fixed(*p.start, decimals);
    std::string flag;
    if (p.identifiable && !*p.identifiable) flag = "not identifiable";
    if (p.nuisance) flag += std::string(flag.empty() ? "" : ", ") + "instrument frame";
    Cell flagCell = text(flag);
    if (p.identifiable && !*p.identifiable) flagCell.cssClass = "flag";
    table.row({text(p.name), numberHtml(valueWithUnit(start, p.unit)),
               numberHtml(valueWithUnit(value, p.unit)), numberHtml(valueWithUnit(s, p.unit)),
               flagCell});
  }
  return table;
}

Table fitTable(const CalibrationReport& report) {
  Table table({text("figure"), numberHtml("before"), numberHtml("after")},
              "Residuals |predicted − measured| over the measured points.");
  const auto row = [&](const std::string& name, const std::optional<double>& before,
                       const std::optional<double>& after) {
    if (!before && !after) return;
    table.row({text(name), before ? number(*before * kUmPerMm, 3, "µm") : text("–"),
               after ? number(*after * kUmPerMm, 3, "µm") : text("–")});
  };
  row("RMS", report.before.rmsMm, report.after.rmsMm);
  row("max", report.before.maxMm, report.after.maxMm);
  // Further numbers a newer calibrate reports per side (per axis, ...), paired by key.
  for (const auto& [key, before] : report.before.more) {
    std::optional<double> after;
    for (const auto& [k, v] : report.after.more) {
      if (k == key) after = v;
    }
    const bool mm = key.size() > 3 && key.compare(key.size() - 3, 3, "_mm") == 0;
    table.row({text(key), mm ? number(before * kUmPerMm, 3, "µm") : number(before, 4),
               after ? (mm ? number(*after * kUmPerMm, 3, "µm") : number(*after, 4)) : text("–")});
  }
  return table;
}

std::string strongCorrelations(const CalibrationReport& report) {
  const std::size_t n = report.parameters.size();
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      const double r = report.correlation[i * n + j];
      if (std::isfinite(r) && std::abs(r) >= 0.9) pairs.emplace_back(std::abs(r), i, j);
    }
  }
  if (pairs.empty()) return paragraph("No pair of parameters is correlated at |r| ≥ 0.9.");
  std::sort(pairs.rbegin(), pairs.rend());
  Table table({text("parameters"), numberHtml("r")},
              "The most strongly correlated pairs (|r| ≥ 0.9): the data barely separate them; "
              "use such parameters together, not one by one.");
  for (std::size_t k = 0; k < std::min<std::size_t>(pairs.size(), 12); ++k) {
    const auto& [magnitude, i, j] = pairs[k];
    table.row({text(report.parameters[i].name + " / " + report.parameters[j].name),
               number(report.correlation[i * n + j], 3)});
  }
  std::string out = table.html();
  if (pairs.size() > 12) {
    out += paragraph(std::to_string(pairs.size() - 12) + " more pairs at |r| ≥ 0.9.");
  }
  return out;
}

std::string residualCharts(Page& page, Context& context, const CalibrationReport& report) {
  const PointResiduals& r = *context.residuals;
  std::string body = "<h3 id=\"calibration-points\">Residuals per point</h3>\n";
  std::string caption = "<b>|residual| per measured point</b>, µm on a log scale: ";
  caption += r.beforeUm.empty() ? "with the model of this report (no template at hand for "
                                  "the residuals before the fit)."
                                : "with the template's start values (before) and with the model "
                                  "of this report (after).";
  body += page.chart("calibration-residuals", charts::residualsChart(r), caption);
  body += "<div class=\"figures\">\n";
  if (!r.beforeUm.empty()) {
    body += page.chart(
        "calibration-histogram-before",
        charts::histogramChart(r.beforeUm, "Before the fit", "#9aa4ae"),
        "<b>Distribution of |residual| before</b> (RMS " + fixed(r.rmsBeforeUm, 2) + " µm).");
  }
  body += page.chart(
      "calibration-histogram-after", charts::histogramChart(r.afterUm, "After the fit", "#0b4f8a"),
      "<b>Distribution of |residual| after</b> (RMS " + fixed(r.rmsAfterUm, 3) + " µm).");
  body += "</div>\n";
  // The recomputed figures must be the calibration's own; say so when they are not.
  if (report.after.rmsMm) {
    const double reported = *report.after.rmsMm * kUmPerMm;
    if (std::abs(reported - r.rmsAfterUm) > 0.02 * reported + 0.005) {
      const std::string text = "the residuals recomputed from the measurements (RMS " +
                               fixed(r.rmsAfterUm, 3) +
                               " µm after) differ from the calibration "
                               "report's (" +
                               fixed(reported, 3) +
                               " µm): the report's model is not the calibration's output, or "
                               "the fit used an instrument frame or weights";
      body += note("Note: " + escape(text) + ".");
      context.notes.push_back(text);
    }
  }
  return body;
}

}  // namespace

void calibrationSection(Page& page, Context& context) {
  if (!context.inputs.calibration) return;
  const CalibrationReport& report = *context.inputs.calibration;
  std::vector<std::pair<std::string, std::string>> subsections;
  std::string intro = "Identified ";
  intro += report.parameters.empty() ? std::string("parameters")
                                     : std::to_string(report.parameters.size()) + " parameters";
  if (report.points) intro += " from " + std::to_string(*report.points) + " measured points";
  if (!report.measurementFile.empty()) {
    intro += " (<code>" + escape(report.measurementFile) + "</code>)";
  }
  if (!report.method.empty()) intro += ", method " + escape(report.method);
  if (!report.loss.empty() && report.loss != "none")
    intro += ", robust loss " + escape(report.loss);
  intro += ".";
  if (report.converged) {
    intro += *report.converged ? " The fit converged" : " <b>The fit did not converge</b>";
    if (report.iterations) intro += " after " + std::to_string(*report.iterations) + " iterations";
    if (!report.termination.empty()) intro += " (" + escape(report.termination) + ")";
    intro += ".";
  }
  if (report.rank && report.parameterCount) {
    intro +=
        " Rank " + std::to_string(*report.rank) + " of " + std::to_string(*report.parameterCount);
    if (report.conditionNumber) intro += ", condition number " + fixed(*report.conditionNumber, 0);
    intro += ".";
  }
  if (report.s0Mm) {
    intro += " Scatter per weighted residual s<sub>0</sub> = " + fixed(*report.s0Mm * kUmPerMm, 3) +
             " µm";
    if (report.dof) intro += " (" + std::to_string(*report.dof) + " degrees of freedom)";
    intro += ".";
  }
  std::string body = paragraph(intro);
  const Table fit = fitTable(report);
  if (!fit.empty()) body += fit.html();

  if (context.residuals) {
    subsections.emplace_back("calibration-points", "Residuals per point");
    body += residualCharts(page, context, report);
  } else {
    context.notes.push_back(
        "calibration residuals per point: the measurement file was not found or not given "
        "(--measurements)");
  }

  if (!report.parameters.empty()) {
    subsections.emplace_back("calibration-parameters", "Parameters");
    body += "<h3 id=\"calibration-parameters\">Parameters</h3>\n" + parameterTable(report).html();
  }
  if (!report.correlation.empty()) {
    subsections.emplace_back("calibration-correlation", "Correlations");
    body += "<h3 id=\"calibration-correlation\">Correlations</h3>\n";
    std::vector<std::string> names;
    for (const CalibrationParameter& p : report.parameters) names.push_back(p.name);
    body +=
        page.chart("calibration-correlation", charts::correlationChart(names, report.correlation),
                   "<b>Correlation of the parameter estimates</b>, lower triangle: orange "
                   "+1, blue −1; blank where a parameter has no standard deviation.");
    body += strongCorrelations(report);
  }
  if (!report.unidentifiable.empty()) {
    subsections.emplace_back("calibration-unidentifiable", "Not identifiable");
    body +=
        "<h3 id=\"calibration-unidentifiable\">What these measurements cannot separate</h3>\n<ul>";
    for (const std::string& d : report.unidentifiable) body += "<li>" + escape(d) + "</li>";
    body += "</ul>\n";
  }
  if (!report.otherFields.empty()) {
    Table more({text("field"), text("value")}, "Further figures of the calibration report.");
    for (const Figure& f : report.otherFields) more.row({text(f.key), text(f.text)});
    body += more.html();
  }
  page.section("calibration", "Calibration", std::move(body), std::move(subsections));
}

}  // namespace volcomp::report::detail
