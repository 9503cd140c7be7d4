// Charts of the model itself: components along their axes, volumetric error maps, grids.

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "chart_parts.hpp"
#include "charts.hpp"
#include "page.hpp"
#include "volcomp/format/numbers.hpp"

namespace volcomp::report::charts {
namespace {

using model::Direction;

// The longer side of a map's plot area, px.
constexpr double kMapSidePx = 300.0;

std::string curveLabel(const ComponentView& component, Direction direction) {
  switch (direction) {
    case Direction::Positive:
      return component.name + " ↑";
    case Direction::Negative:
      return component.name + " ↓";
    case Direction::Unknown:
      break;
  }
  return component.name;
}

// Plot size keeping the plane's proportions (within 1:3), longer side kMapSidePx.
std::array<double, 2> plotSize(double spanA, double spanB) {
  const double ratio = std::clamp(spanB / spanA, 1.0 / 3.0, 3.0);
  if (ratio <= 1.0) return {kMapSidePx, std::round(kMapSidePx * ratio)};
  return {std::round(kMapSidePx / ratio), kMapSidePx};
}

struct MapFrame {
  double aLo, aHi, bLo, bHi, width, height;
};

MapFrame frameOf(const ErrorMap& map) {
  MapFrame f{
      map.cells.front().a0, map.cells.back().a1, map.cells.front().b0, map.cells.back().b1, 0, 0};
  const auto size = plotSize(f.aHi - f.aLo, f.bHi - f.bLo);
  f.width = size[0];
  f.height = size[1];
  return f;
}

// The cells as columns: centre, the values both maps use (errors to 1 nm), the in-plane error
// where an arrow is drawn (null elsewhere). The cells of a plane are all the same size.
void addCells(Json& spec, const ErrorMap& map, bool withArrows) {
  std::vector<std::pair<std::string, Json>> columns;
  for (const char* field : {"a", "b", "m", "w", "ex", "ey", "ez", "u", "v"}) {
    columns.emplace_back(field, Json::array());
  }
  for (const MapCell& c : map.cells) {
    const bool arrow = withArrows && c.arrow;
    const double values[] = {c.a,           c.b,           c.magnitude,  c.outOfPlane,
                             c.errorUm.x(), c.errorUm.y(), c.errorUm.z()};
    for (std::size_t k = 0; k < 7; ++k) columns[k].second.push_back(rounded(values[k], 1e-3));
    columns[7].second.push_back(arrow ? rounded(c.inPlaneA, 1e-3) : Json(nullptr));
    columns[8].second.push_back(arrow ? rounded(c.inPlaneB, 1e-3) : Json(nullptr));
  }
  if (!withArrows) columns.resize(7);
  const MapCell& first = map.cells.front();
  spec["signals"].push_back(Json{{"name", "da"}, {"value", rounded(first.a1 - first.a0, 1e-6)}});
  spec["signals"].push_back(Json{{"name", "db"}, {"value", rounded(first.b1 - first.b0, 1e-6)}});
  addColumns(spec, "cells", map.cells.size(), columns);
}

std::string tooltipOf(const ErrorMap& map) {
  const std::string a = axisName(map.plane.across), b = axisName(map.plane.up);
  return "{'" + a + "': format(datum.a, '.1f') + ' mm', '" + b +
         "': format(datum.b, '.1f') + ' mm', '|E|': format(datum.m, '.2f') + ' µm', "
         "'EX': format(datum.ex, '.2f') + ' µm', 'EY': format(datum.ey, '.2f') + ' µm', "
         "'EZ': format(datum.ez, '.2f') + ' µm'}";
}

Json mapBase(const ErrorMap& map, const MapFrame& f, bool withArrows) {
  const std::string a = axisName(map.plane.across), b = axisName(map.plane.up);
  Json spec{
      {"width", f.width},
      {"height", f.height},
      {"padding", 4},
      {"autosize", "pad"},
      {"signals", Json::array()},
      {"scales", Json::array({linearScale("x", Json::array({f.aLo, f.aHi}), "width"),
                              linearScale("y", Json::array({f.bLo, f.bHi}), "height")})},
      {"axes", Json::array({axis("bottom", "x", a + " (mm)"), axis("left", "y", b + " (mm)")})}};
  addCells(spec, map, withArrows);
  return spec;
}

Json cellMarks(const std::string& field, const std::string& tooltip) {
  return Json{{"type", "rect"},
              {"name", "cell-rects"},
              {"from", {{"data", "cells"}}},
              {"encode",
               {{"enter",
                 {{"x", {{"signal", "scale('x', datum.a - da / 2)"}}},
                  {"x2", {{"signal", "scale('x', datum.a + da / 2)"}}},
                  {"y", {{"signal", "scale('y', datum.b + db / 2)"}}},
                  {"y2", {{"signal", "scale('y', datum.b - db / 2)"}}},
                  {"fill", channel("colour", field)},
                  {"tooltip", {{"signal", tooltip}}}}}}}};
}

// 1, 2 or 5 times a power of ten, at most `value`.
double roundDown125(double value) {
  if (!(value > 0.0)) return 1.0;
  const double power = std::pow(10.0, std::floor(std::log10(value)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * power <= value) return m * power;
  }
  return power;
}

}  // namespace

Json rounded(double value, double quantum) {
  if (!std::isfinite(value)) return nullptr;
  const double r = std::round(value / quantum) * quantum;
  // Shortest text for the rounded number: strip the binary noise of r.
  return std::strtod(format::general(r, 12).c_str(), nullptr);
}

const char* axisColour(int axis) {
  static const char* const colours[3] = {"#1f6fb4", "#e8710a", "#2a9d3f"};
  return colours[std::clamp(axis, 0, 2)];
}

Json componentChart(std::span<const ComponentView* const> components, const std::string& axisText,
                    bool angular) {
  Json curveLabels = Json::array(), xs = Json::array(), ys = Json::array(), nodes = Json::array();
  Json labels = Json::array(), colours = Json::array(), dashes = Json::array();
  for (const ComponentView* component : components) {
    // EXK..EZK and EAK..ECK: the error's own direction picks the colour.
    const int direction = component->index % 6 % 3;
    for (std::size_t k = 0; k < component->curves.size(); ++k) {
      const ComponentCurve& curve = component->curves[k];
      const std::string label = curveLabel(*component, curve.direction);
      labels.push_back(label);
      colours.push_back(axisColour(direction));
      dashes.push_back(curve.direction == Direction::Negative ? Json::array({6, 3})
                                                              : Json::array({1, 0}));
      for (std::size_t i = 0; i < curve.positionsMm.size(); ++i) {
        curveLabels.push_back(label);
        xs.push_back(rounded(curve.positionsMm[i], 1e-3));
        ys.push_back(rounded(curve.values[i], 1e-4));
      }
      for (const auto& [q, value] : component->nodes[k]) {
        nodes.push_back({{"c", label}, {"x", rounded(q, 1e-3)}, {"y", rounded(value, 1e-4)}});
      }
    }
  }
  const std::string unit = angular ? "µrad" : "µm";
  const std::string tooltip = "{'component': datum.c, '" + axisText +
                              "': format(datum.x, '.1f') + ' mm', 'value': format(datum.y, '.3f') "
                              "+ ' " +
                              unit + "'}";
  Json y = linearScale("y", dataDomain({{"curves", "y"}, {"nodes", "y"}}), "height");
  y["zero"] = true;
  y["nice"] = true;
  Json spec{
      {"width", 380},
      {"height", 200},
      {"padding", 4},
      {"autosize", "pad"},
      {"scales", Json::array({linearScale("x", dataDomain({{"curves", "x"}}), "width"), y,
                              ordinalScale("colour", labels, colours),
                              ordinalScale("dash", labels, dashes)})},
      {"axes",
       Json::array({axis("bottom", "x", axisText + " position (mm)"),
                    gridAxis("left", "y", (angular ? "rotation (" : "error (") + unit + ")")})},
      {"legends", Json::array({lineLegend(true)})},
      {"marks", Json::array({zeroRule("y"), seriesLines("curves", "c", "x", "y", "curve", true),
                             Json{{"type", "symbol"},
                                  {"name", "node-points"},
                                  {"from", {{"data", "nodes"}}},
                                  {"encode",
                                   {{"enter",
                                     {{"x", channel("x", "x")},
                                      {"y", channel("y", "y")},
                                      {"size", {{"value", 16}}},
                                      {"fill", {{"value", "#ffffff"}}},
                                      {"stroke", channel("colour", "c")},
                                      {"strokeWidth", {{"value", 1.2}}},
                                      {"tooltip", {{"signal", tooltip}}}}}}}}})}};
  addColumns(spec, "curves", xs.size(), {{"c", curveLabels}, {"x", xs}, {"y", ys}});
  spec["data"].push_back(Json{{"name", "nodes"}, {"values", nodes}});
  return spec;
}

double mapCellPx(const ErrorMap& map) {
  const MapFrame f = frameOf(map);
  return std::min(f.width / map.plane.cellsAcross, f.height / map.plane.cellsUp);
}

Json magnitudeMap(const ErrorMap& map, const MapScales& scales) {
  const MapFrame f = frameOf(map);
  Json spec = mapBase(map, f, true);
  spec["scales"].push_back(
      Json{{"name", "colour"},
           {"type", "linear"},
           {"domain", Json::array({0.0, rounded(scales.magnitudeMaxUm, 1e-3)})},
           {"range", {{"scheme", "yelloworangered"}}},
           {"zero", true}});
  spec["signals"].push_back(Json{{"name", "k"}, {"value", scales.arrowPxPerUm}});
  spec["legends"] = Json::array({gradientLegend("colour", "|E| (µm)", f.height)});
  const double referenceUm = roundDown125(scales.inPlaneMaxUm);
  const double referencePx = referenceUm * scales.arrowPxPerUm;
  const std::string tipX = "scale('x', datum.a) + datum.u * k";
  const std::string tipY = "scale('y', datum.b) - datum.v * k";
  const std::string arrowFilter = "isValid(datum.u)";
  spec["data"].push_back(
      Json{{"name", "arrows"},
           {"source", "cells"},
           {"transform", Json::array({Json{{"type", "filter"}, {"expr", arrowFilter}}})}});
  spec["data"].push_back(Json{
      {"name", "reference"},
      {"values", Json::array({Json{{"x0", f.width - referencePx},
                                   {"x1", f.width},
                                   {"label", "arrow scale: " + label(referenceUm) + " µm"}}})}});
  Json marks = Json::array({cellMarks("m", tooltipOf(map))});
  marks.push_back(Json{{"type", "rule"},
                       {"name", "arrow-lines"},
                       {"from", {{"data", "arrows"}}},
                       {"encode",
                        {{"enter",
                          {{"x", channel("x", "a")},
                           {"y", channel("y", "b")},
                           {"x2", {{"signal", tipX}}},
                           {"y2", {{"signal", tipY}}},
                           {"stroke", {{"value", "#1b1f24"}}},
                           {"strokeWidth", {{"value", 1.2}}}}}}}});
  marks.push_back(
      Json{{"type", "symbol"},
           {"name", "arrowheads"},
           {"from", {{"data", "arrows"}}},
           {"encode",
            {{"enter",
              {{"x", {{"signal", tipX}}},
               {"y", {{"signal", tipY}}},
               {"shape", {{"value", "triangle"}}},
               {"size", {{"value", 22}}},
               {"angle", {{"signal", "atan2(datum.u, datum.v) * 180 / PI"}}},
               {"fill", {{"value", "#1b1f24"}}},
               {"fillOpacity",
                {{"signal", "sqrt(datum.u * datum.u + datum.v * datum.v) * k > 4 ? 1 : 0"}}}}}}}});
  // A reference arrow under the plot, right-aligned, as the scale of the arrows.
  marks.push_back(Json{{"type", "rule"},
                       {"name", "reference-arrow"},
                       {"from", {{"data", "reference"}}},
                       {"encode",
                        {{"enter",
                          {{"x", {{"field", "x0"}}},
                           {"x2", {{"field", "x1"}}},
                           {"y", {{"signal", "height + 44"}}},
                           {"stroke", {{"value", "#1b1f24"}}},
                           {"strokeWidth", {{"value", 1.2}}}}}}}});
  marks.push_back(Json{{"type", "symbol"},
                       {"name", "reference-head"},
                       {"from", {{"data", "reference"}}},
                       {"encode",
                        {{"enter",
                          {{"x", {{"field", "x1"}}},
                           {"y", {{"signal", "height + 44"}}},
                           {"shape", {{"value", "triangle"}}},
                           {"size", {{"value", 22}}},
                           {"angle", {{"value", 90}}},
                           {"fill", {{"value", "#1b1f24"}}}}}}}});
  marks.push_back(Json{{"type", "text"},
                       {"name", "reference-label"},
                       {"from", {{"data", "reference"}}},
                       {"encode",
                        {{"enter",
                          {{"x", {{"field", "x0"}, {"offset", -6}}},
                           {"y", {{"signal", "height + 44"}}},
                           {"text", {{"field", "label"}}},
                           {"align", {{"value", "right"}}},
                           {"baseline", {{"value", "middle"}}}}}}}});
  spec["marks"] = std::move(marks);
  return spec;
}

Json outOfPlaneMap(const ErrorMap& map, const MapScales& scales) {
  const MapFrame f = frameOf(map);
  Json spec = mapBase(map, f, false);
  const double m = rounded(scales.outOfPlaneMaxUm, 1e-3).get<double>();
  spec["scales"].push_back(Json{{"name", "colour"},
                                {"type", "linear"},
                                {"domain", Json::array({-m, m})},
                                {"domainMid", 0},
                                {"range", {{"scheme", "blueorange"}}}});
  const std::string normal = "E" + axisName(normalAxis(map.plane));
  spec["legends"] = Json::array({gradientLegend("colour", normal + " (µm)", f.height)});
  spec["marks"] = Json::array({cellMarks("w", tooltipOf(map))});
  return spec;
}

Json gridChart(const model::GridSpec& grid) {
  // Node-centred cells: each node's cell reaches halfway to its neighbours.
  const auto edges = [](const std::vector<double>& nodes, std::size_t i) {
    const double lo = i == 0 ? nodes[0] : 0.5 * (nodes[i - 1] + nodes[i]);
    const double hi = i + 1 == nodes.size() ? nodes[i] : 0.5 * (nodes[i] + nodes[i + 1]);
    return std::array<double, 2>{lo, hi};
  };
  const auto& na = grid.axesMm[0];
  const auto& nb = grid.axesMm[1];
  Json rows = Json::array();
  double peak = 0.0;
  for (std::size_t i = 0; i < na.size(); ++i) {
    for (std::size_t j = 0; j < nb.size(); ++j) {
      // For a 3-D grid, the first slice of its third axis.
      const std::size_t index =
          grid.over.size() == 2 ? i * nb.size() + j : (i * nb.size() + j) * grid.axesMm[2].size();
      const double value = grid.valuesMm[index] * kUmPerMm;
      peak = std::max(peak, std::abs(value));
      const auto [a0, a1] = edges(na, i);
      const auto [b0, b1] = edges(nb, j);
      rows.push_back({{"a0", a0},
                      {"a1", a1},
                      {"b0", b0},
                      {"b1", b1},
                      {"a", na[i]},
                      {"b", nb[j]},
                      {"v", rounded(value, 1e-4)}});
    }
  }
  const std::string a = axisName(grid.over[0]), b = axisName(grid.over[1]);
  const std::string component = std::string("E") + "XYZ"[std::clamp(grid.component, 0, 2)];
  const auto size = plotSize(na.back() - na.front(), nb.back() - nb.front());
  const double m = rounded(std::max(peak, 1e-3), 1e-3).get<double>();
  const std::string tooltip = "{'" + a + "': datum.a + ' mm', '" + b + "': datum.b + ' mm', '" +
                              component + "': format(datum.v, '.2f') + ' µm'}";
  return Json{
      {"width", size[0]},
      {"height", size[1]},
      {"padding", 4},
      {"autosize", "pad"},
      {"data", Json::array({Json{{"name", "cells"}, {"values", rows}}})},
      {"scales", Json::array({linearScale("x", Json::array({na.front(), na.back()}), "width"),
                              linearScale("y", Json::array({nb.front(), nb.back()}), "height"),
                              Json{{"name", "colour"},
                                   {"type", "linear"},
                                   {"domain", Json::array({-m, m})},
                                   {"domainMid", 0},
                                   {"range", {{"scheme", "blueorange"}}}}})},
      {"axes", Json::array({axis("bottom", "x", a + " (mm)"), axis("left", "y", b + " (mm)")})},
      {"legends", Json::array({gradientLegend("colour", component + " (µm)", size[1])})},
      {"marks", Json::array({Json{{"type", "rect"},
                                  {"name", "cell-rects"},
                                  {"from", {{"data", "cells"}}},
                                  {"encode",
                                   {{"enter",
                                     {{"x", channel("x", "a0")},
                                      {"x2", channel("x", "a1")},
                                      {"y", channel("y", "b1")},
                                      {"y2", channel("y", "b0")},
                                      {"fill", channel("colour", "v")},
                                      {"tooltip", {{"signal", tooltip}}}}}}}}})}};
}

}  // namespace volcomp::report::charts
