// Section "ISO 230-2 positioning": the standard chart and tables of each evaluated axis.

#include "charts.hpp"
#include "sections.hpp"

namespace volcomp::report::detail {
namespace {

Cell optionalUm(const std::optional<double>& value) {
  return value ? number(*value, 2) : text("–");
}

Table targetTable(const IsoAxis& axis) {
  Table table(
      {numberHtml("target P<sub>i</sub> (mm)"), numberHtml("x̄↑<sub>i</sub>"),
       numberHtml("x̄↓<sub>i</sub>"), numberHtml("x̄<sub>i</sub>"), numberHtml("B<sub>i</sub>"),
       numberHtml("s↑<sub>i</sub>"), numberHtml("s↓<sub>i</sub>"), numberHtml("R↑<sub>i</sub>"),
       numberHtml("R↓<sub>i</sub>"), numberHtml("R<sub>i</sub>")},
      "Per target position, µm: mean unidirectional deviations, mean bidirectional "
      "deviation, reversal value, standard uncertainty estimators and repeatabilities.");
  for (const IsoTarget& t : axis.targets) {
    table.row({number(t.positionMm, 3), optionalUm(t.meanUp), optionalUm(t.meanDown),
               optionalUm(t.mean), optionalUm(t.reversal), optionalUm(t.sUp), optionalUm(t.sDown),
               optionalUm(t.repeatUp), optionalUm(t.repeatDown), optionalUm(t.repeat)});
  }
  return table;
}

}  // namespace

void isoSection(Page& page, Context& context) {
  if (context.inputs.iso.empty()) return;
  std::string body = paragraph(
      "Positioning accuracy and repeatability of linear axes after ISO 230-2:2014. The chart "
      "of each axis shows the mean positional deviations at "
      "each target approached in the positive (x̄↑) and negative (x̄↓) direction with bands of "
      "±2s, the mean bidirectional deviation x̄ and the measured runs.");
  std::vector<std::pair<std::string, std::string>> subsections;
  for (const IsoAxis& axis : context.inputs.iso) {
    if (axis.targets.empty()) continue;
    const std::string name = axis.axis ? axisName(*axis.axis) : "axis";
    std::string id = "iso-" + name;
    for (char& c : id) {
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
    }
    subsections.emplace_back(id, "Axis " + name);
    body += "<h3 id=\"" + id + "\">Axis " + escape(name) + "</h3>\n";
    std::string caption = "<b>ISO 230-2, axis " + escape(name) +
                          "</b>: mean deviations in µm "
                          "against the target position, shaded ±2s, circles the single runs";
    if (axis.runsUp > 0) {
      caption += ", " + std::to_string(axis.runsUp) + " runs in + and " +
                 std::to_string(axis.runsDown) + " in −";
    }
    caption += "; from <code>" + escape(axis.source.empty() ? axis.file : axis.source) + "</code>";
    body += page.chart(id + "-chart", charts::isoChart(axis), caption + ".");
    if (!axis.figures.empty()) {
      Table figures({text("symbol"), text("figure"), numberHtml("value")},
                    "Figures of the axis (ISO 230-2:2014, clause 2).");
      for (const IsoFigure& f : axis.figures) {
        figures.row({text(f.symbol), text(f.meaning), number(f.valueUm, 2, "µm")});
      }
      body += figures.html();
    }
    body += targetTable(axis).html();
    for (const std::string& w : axis.warnings) body += note("ISO 230-2: " + escape(w));
  }
  page.section("iso230-2", "ISO 230-2 positioning", std::move(body), std::move(subsections));
}

}  // namespace volcomp::report::detail
