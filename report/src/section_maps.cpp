// Section "Volumetric error maps": E over XY planes at a few Z levels, and over XZ and YZ.

#include <algorithm>

#include "charts.hpp"
#include "sections.hpp"

namespace volcomp::report::detail {
namespace {

std::string planeTitle(const PlaneSpec& plane) {
  return axisName(plane.across) + axisName(plane.up) + " plane at " + axisName(normalAxis(plane)) +
         " = " + fixed(plane.levelMm, 0) + " mm";
}

std::string planeId(const PlaneSpec& plane) {
  std::string level = fixed(plane.levelMm, 0);
  for (char& c : level) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = 'm';
  }
  return "map-" + axisName(plane.across) + axisName(plane.up) + "-" + level;
}

}  // namespace

void mapsSection(Page& page, Context& context) {
  if (context.model == nullptr) return;
  model::Workspace ws;
  std::vector<ErrorMap> maps;
  for (const PlaneSpec& plane :
       reportPlanes(context.volume, context.options.zLevelsMm, context.options.mapResolution)) {
    maps.push_back(errorMap(*context.model, ws, context.volume, plane));
  }
  // One colour scale and one arrow scale for every map.
  charts::MapScales scales;
  double cellPx = 1e9;
  for (const ErrorMap& map : maps) {
    scales.magnitudeMaxUm = std::max(scales.magnitudeMaxUm, map.maxMagnitudeUm);
    scales.outOfPlaneMaxUm = std::max(scales.outOfPlaneMaxUm, map.maxAbsOutOfPlaneUm);
    scales.inPlaneMaxUm = std::max(scales.inPlaneMaxUm, map.maxInPlaneUm);
    cellPx = std::min(cellPx, charts::mapCellPx(map));
  }
  scales.arrowPxPerUm = 0.9 * 2.0 * cellPx / scales.inPlaneMaxUm;

  const Eigen::Vector3d& tool = context.model->toolMm();
  std::string body = paragraph(
      "The tool-tip error E = actual − nominal position that the model predicts without "
      "compensation, over planes through the working volume. Left: the magnitude |E| as colour, "
      "the part "
      "of E in the plane as arrows. Right: the part of E normal to the plane (blue negative, "
      "orange positive); for an XY plane this is the classic map of the deflection over the "
      "table. All maps share one colour scale per kind (|E| 0 to " +
      fixed(scales.magnitudeMaxUm, 1) + " µm; normal part ±" + fixed(scales.outOfPlaneMaxUm, 1) +
      " µm) and one arrow scale. Tool offset " + fixed(tool.x(), 0) + ", " + fixed(tool.y(), 0) +
      ", " + fixed(tool.z(), 0) +
      " mm; bidirectional tables at the mean of their two curves; evaluated at the cell centres.");
  std::vector<std::pair<std::string, std::string>> subsections;
  for (const ErrorMap& map : maps) {
    const std::string id = planeId(map.plane);
    const std::string title = planeTitle(map.plane);
    subsections.emplace_back(id, title);
    const std::string normal = "E" + axisName(normalAxis(map.plane));
    body += "<h3 id=\"" + id + "\">" + escape(title) + "</h3>\n<div class=\"figures\">\n";
    body += page.chart(id + "-magnitude", charts::magnitudeMap(map, scales),
                       "<b>|E|</b> with the in-plane error as arrows; max " +
                           fixed(map.maxMagnitudeUm, 2) + " µm in this plane.");
    body += page.chart(id + "-normal", charts::outOfPlaneMap(map, scales),
                       "<b>" + normal + "</b>, the error normal to the plane; |" + normal +
                           "| up to " + fixed(map.maxAbsOutOfPlaneUm, 2) + " µm.");
    body += "</div>\n";
  }
  page.section("maps", "Volumetric error maps", std::move(body), std::move(subsections));
}

}  // namespace volcomp::report::detail
