// Section "Error components": every component against its axis position, squareness, grids.

#include <cmath>
#include <variant>

#include "charts.hpp"
#include "sections.hpp"

namespace volcomp::report::detail {
namespace {

constexpr double kArcsecPerUrad = 0.206264806;

constexpr double kDegPerRad = 57.29577951308232;

// A D-H chain: its links with their deviations (no component curves or maps: those are drawn for
// 3-axis machine models over X, Y, Z).
std::string dhBody(const model::DhChainSpec& chain) {
  std::string body = paragraph(
      std::string("This model is a Denavit-Hartenberg chain (") +
      (chain.convention == model::DhConvention::Modified ? "modified" : "standard") +
      " convention). Component curves and volumetric maps are drawn for 3-axis machine models; "
      "the chain's links and their deviations are:");
  Table links({text("link"), text("joint"), numberHtml("θ (°)"), numberHtml("d (mm)"),
               numberHtml("a (mm)"), numberHtml("α (°)"), numberHtml("Δθ (°)"),
               numberHtml("Δd (mm)"), numberHtml("Δa (mm)"), numberHtml("Δα (°)")},
              "Nominal parameters and deviations (actual = nominal + deviation); a fixed "
              "transform lists its rotations about X, Y, Z and its translation instead.");
  for (std::size_t i = 0; i < chain.links.size(); ++i) {
    const model::DhLinkSpec& l = chain.links[i];
    const char* joint = l.joint == model::JointType::Prismatic  ? "prismatic"
                        : l.joint == model::JointType::Revolute ? "revolute"
                                                                : "fixed";
    if (l.isTransform) {
      const auto deg = [](const Eigen::Vector3d& v) {
        return fixed(v.x() * kDegPerRad, 6) + ", " + fixed(v.y() * kDegPerRad, 6) + ", " +
               fixed(v.z() * kDegPerRad, 6) + "°";
      };
      const auto mm = [](const Eigen::Vector3d& v) {
        return fixed(v.x(), 3) + ", " + fixed(v.y(), 3) + ", " + fixed(v.z(), 3) + " mm";
      };
      links.row({text(std::to_string(i + 1)), text("fixed transform"),
                 Cell{"rotation " + deg(l.rotationRad) + ", translation " + mm(l.translationMm) +
                          "; deviations " + deg(l.dRotationRad) + ", " + mm(l.dTranslationMm),
                      false,
                      {}},
                 text(""), text(""), text(""), text(""), text(""), text(""), text("")});
      continue;
    }
    links.row({text(std::to_string(i + 1)), text(joint), number(l.thetaRad * kDegPerRad, 4),
               number(l.dMm, 3), number(l.aMm, 3), number(l.alphaRad * kDegPerRad, 4),
               number(l.dThetaRad * kDegPerRad, 7), number(l.dDMm, 4), number(l.dAMm, 4),
               number(l.dAlphaRad * kDegPerRad, 7)});
  }
  return body + links.html();
}

Table componentTable(const std::vector<ComponentView>& views) {
  Table table({text("component"), text("meaning"), text("kind"), numberHtml("peak |value|")},
              "Motion errors (ISO 230-1 names) as the model gives them; peak over the axis range.");
  for (const ComponentView& v : views) {
    table.row({text(v.name), text(v.meaning), text(v.kind),
               number(v.peakAbs, decimalsFor(v.peakAbs, 3), v.unit)});
  }
  return table;
}

}  // namespace

void modelSection(Page& page, Context& context) {
  if (context.model == nullptr) {
    const auto* chain = std::get_if<model::DhChainSpec>(&context.inputs.model.spec);
    page.section("components", "Error components", chain ? dhBody(*chain) : std::string());
    context.notes.push_back("the model is a D-H chain: no component curves or error maps");
    return;
  }
  const std::vector<ComponentView> views =
      componentViews(*context.model, context.volume, context.options.curveSamples);
  std::string body = paragraph(
      "Each error motion of the model against the position of its axis, over the working "
      "volume: translations in µm, rotations in µrad (1&#8239;µrad = 0.206″). A bidirectional "
      "table has two curves: ↑ while the axis moves in +, ↓ (dashed) while it moves in −. "
      "Circles mark the nodes of measured tables.");
  std::vector<std::pair<std::string, std::string>> subsections;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<const ComponentView*> translations, rotations;
    for (const ComponentView& v : views) {
      if (static_cast<int>(v.axis) != axis) continue;
      (v.angular ? rotations : translations).push_back(&v);
    }
    if (translations.empty() && rotations.empty()) continue;
    const std::string name = axisName(static_cast<model::Axis>(axis));
    const std::string id = "components-" + name;
    subsections.emplace_back(id, "Axis " + name);
    body += "<h3 id=\"" + id + "\">Axis " + name + "</h3>\n<div class=\"figures\">\n";
    if (!translations.empty()) {
      body += page.chart(id + "-translations", charts::componentChart(translations, name, false),
                         "<b>Translations of " + name + "</b>: positioning E" + name + name +
                             " and straightness, µm.");
    }
    if (!rotations.empty()) {
      body += page.chart(id + "-rotations", charts::componentChart(rotations, name, true),
                         "<b>Rotations of " + name + "</b>: roll, pitch and yaw, µrad.");
    }
    body += "</div>\n";
  }
  if (views.empty())
    body += paragraph("<span class=\"absent\">The model has no motion errors.</span>");
  body += "<h3 id=\"components-table\">All components</h3>\n";
  subsections.emplace_back("components-table", "All components");
  if (!views.empty()) body += componentTable(views).html();

  const auto locations = locationErrors(*context.model);
  Table squareness({text("location error"), numberHtml("value"), numberHtml("value")},
                   "Squareness and orientation of the axes' lines of motion (constants).");
  for (const auto& [name, urad] : locations) {
    squareness.row({text(name), number(urad, 2, "µrad"), number(urad * kArcsecPerUrad, 2, "″")});
  }
  if (!squareness.empty()) body += squareness.html();

  const auto& grids = context.model->grids();
  if (!grids.empty()) {
    body += "<h3 id=\"components-grids\">Grid maps</h3>\n<div class=\"figures\">\n";
    subsections.emplace_back("components-grids", "Grid maps");
    for (std::size_t g = 0; g < grids.size(); ++g) {
      const model::GridSpec& grid = grids[g].spec();
      std::string over;
      for (model::Axis a : grid.over) over += axisName(a);
      const std::string component = std::string("E") + "XYZ"[grid.component];
      std::string caption = "<b>Grid " + std::to_string(g + 1) + "</b>: " + component + " over " +
                            over + ", µm, at its nodes.";
      if (grid.over.size() == 3) {
        caption += " The first " + axisName(grid.over[2]) + " slice of the 3-D grid.";
      }
      body += page.chart("grid-" + std::to_string(g + 1), charts::gridChart(grid), caption);
    }
    body += "</div>\n";
  }
  page.section("components", "Error components", std::move(body), std::move(subsections));
}

}  // namespace volcomp::report::detail
