// Charts of a calibration: residuals per point, their histograms, the correlation matrix.

#include <algorithm>
#include <cmath>

#include "chart_parts.hpp"
#include "charts.hpp"

namespace volcomp::report::charts {
namespace {

constexpr const char* kBefore = "before (template)";
constexpr const char* kAfter = "after (this model)";
constexpr const char* kBeforeColour = "#9aa4ae";
constexpr const char* kAfterColour = "#0b4f8a";

// On a log axis a residual of exactly zero has no place: shown at 0.1 nm.
constexpr double kLogFloorUm = 1e-4;

}  // namespace

Json residualsChart(const PointResiduals& residuals) {
  // Rows: the points before the fit (when known), then the same points after it.
  const std::size_t n = residuals.afterUm.size();
  Json r = Json::array(), lines = Json::array();
  for (const std::vector<double>* side : {&residuals.beforeUm, &residuals.afterUm}) {
    for (double value : *side) r.push_back(rounded(std::max(value, kLogFloorUm), 1e-5));
  }
  for (int line : residuals.lines) lines.push_back(line);
  const std::size_t before = residuals.beforeUm.size();
  const std::string count = std::to_string(before);
  Json series = Json::array(), colours = Json::array();
  if (!residuals.beforeUm.empty()) {
    series.push_back(kBefore);
    colours.push_back(kBeforeColour);
  }
  series.push_back(kAfter);
  colours.push_back(kAfterColour);
  Json y = Json{{"name", "y"},
                {"type", "log"},
                {"domain", dataDomain({{"points", "r"}})},
                {"range", "height"},
                {"nice", true}};
  const double size = n > 2000 ? 6 : 14;
  Json spec{{"width", 820},
            {"height", 220},
            {"padding", 4},
            {"autosize", "pad"},
            {"signals", Json::array({Json{{"name", "lines"}, {"value", lines}}})},
            {"scales", Json::array({linearScale("x", dataDomain({{"points", "n"}}), "width"), y,
                                    ordinalScale("colour", series, colours)})},
            {"axes", Json::array({axis("bottom", "x", "measured point (in file order)"),
                                  gridAxis("left", "y", "|residual| (µm, log scale)")})},
            {"legends", Json::array({swatchLegend("colour")})},
            {"marks",
             Json::array({Json{{"type", "symbol"},
                               {"name", "residuals"},
                               {"from", {{"data", "points"}}},
                               {"encode",
                                {{"enter",
                                  {{"x", channel("x", "n")},
                                   {"y", channel("y", "r")},
                                   {"size", {{"value", size}}},
                                   {"fill", channel("colour", "s")},
                                   {"fillOpacity", {{"value", 0.75}}},
                                   {"tooltip",
                                    {{"signal",
                                      "{'point': datum.n, 'line': datum.line, 'fit': datum.s, "
                                      "'|residual|': format(datum.r, '.3f') + ' µm'}"}}}}}}}}})}};
  const std::string point = "(datum.row < " + count + " ? datum.row : datum.row - " + count + ")";
  addColumns(spec, "points", before + n, {{"r", r}},
             Json::array(
                 {Json{{"type", "formula"}, {"expr", point + " + 1"}, {"as", "n"}},
                  Json{{"type", "formula"}, {"expr", "lines[" + point + "]"}, {"as", "line"}},
                  Json{{"type", "formula"},
                       {"expr", "datum.row < " + count + " ? '" + kBefore + "' : '" + kAfter + "'"},
                       {"as", "s"}}}));
  return spec;
}

Json histogramChart(std::span<const double> valuesUm, const std::string& title,
                    const std::string& colour) {
  Json values = Json::array();
  for (double v : valuesUm) values.push_back(rounded(v, 1e-5));
  Json spec{
      {"width", 370},
      {"height", 170},
      {"padding", 4},
      {"autosize", "pad"},
      {"title", title},
      {"data", Json::array({Json{
                   {"name", "bins"},
                   {"source", "residuals"},
                   {"transform",
                    Json::array({Json{{"type", "extent"}, {"field", "v"}, {"signal", "extent"}},
                                 Json{{"type", "bin"},
                                      {"field", "v"},
                                      {"extent", {{"signal", "extent"}}},
                                      {"maxbins", 30}},
                                 Json{{"type", "aggregate"},
                                      {"groupby", Json::array({"bin0", "bin1"})}}})}}})},
      {"scales",
       Json::array({linearScale("x", dataDomain({{"bins", "bin0"}, {"bins", "bin1"}}), "width"),
                    Json{{"name", "y"},
                         {"type", "linear"},
                         {"domain", dataDomain({{"bins", "count"}})},
                         {"range", "height"},
                         {"zero", true},
                         {"nice", true}}})},
      {"axes",
       Json::array({axis("bottom", "x", "|residual| (µm)"), gridAxis("left", "y", "points")})},
      {"marks", Json::array({Json{
                    {"type", "rect"},
                    {"name", "bars"},
                    {"from", {{"data", "bins"}}},
                    {"encode",
                     {{"enter",
                       {{"x", {{"scale", "x"}, {"field", "bin0"}, {"offset", 0.5}}},
                        {"x2", {{"scale", "x"}, {"field", "bin1"}, {"offset", -0.5}}},
                        {"y", channel("y", "count")},
                        {"y2", {{"scale", "y"}, {"value", 0}}},
                        {"fill", {{"value", colour}}},
                        {"tooltip",
                         {{"signal",
                           "{'from': format(datum.bin0, '.3f') + ' µm', 'to': "
                           "format(datum.bin1, '.3f') + ' µm', 'points': datum.count}"}}}}}}}}})}};
  // The values first: "bins" is computed from them.
  Json bins = spec["data"][0];
  spec["data"] = Json::array();
  addColumns(spec, "residuals", valuesUm.size(), {{"v", values}});
  spec["data"].push_back(std::move(bins));
  return spec;
}

Json correlationChart(const std::vector<std::string>& names, std::span<const double> matrix) {
  // The matrix goes in as one flat signal (3 decimals) and becomes cells inside Vega: a third of
  // the size of one object per cell for 147 parameters.
  const std::size_t n = names.size();
  Json flat = Json::array();
  for (double r : matrix) flat.push_back(rounded(r, 1e-3));
  Json nameList = Json::array();
  for (const std::string& name : names) nameList.push_back(name);
  const double side = std::clamp(10.0 * static_cast<double>(n), 160.0, 640.0);
  const std::string index = "sequence(" + std::to_string(n) + ")";
  return Json{
      {"width", side},
      {"height", side},
      {"padding", 4},
      {"autosize", "pad"},
      {"signals",
       Json::array({Json{{"name", "n"}, {"value", n}}, Json{{"name", "names"}, {"value", nameList}},
                    Json{{"name", "r"}, {"value", flat}}})},
      {"data",
       Json::array({Json{
           {"name", "cells"},
           {"transform",
            Json::array({Json{{"type", "sequence"}, {"start", 0}, {"stop", n * n}},
                         Json{{"type", "formula"}, {"expr", "floor(datum.data / n)"}, {"as", "i"}},
                         Json{{"type", "formula"}, {"expr", "datum.data % n"}, {"as", "j"}},
                         Json{{"type", "formula"}, {"expr", "r[datum.data]"}, {"as", "r"}},
                         Json{{"type", "filter"},
                              {"expr", "datum.j <= datum.i && isValid(datum.r)"}}})}}})},
      {"scales", Json::array({Json{{"name", "x"},
                                   {"type", "band"},
                                   {"domain", {{"signal", index}}},
                                   {"range", "width"}},
                              Json{{"name", "y"},
                                   {"type", "band"},
                                   {"domain", {{"signal", index}}},
                                   {"range", "height"}},
                              Json{{"name", "colour"},
                                   {"type", "linear"},
                                   {"domain", Json::array({-1, 1})},
                                   {"domainMid", 0},
                                   {"range", {{"scheme", "blueorange"}}}}})},
      {"axes",
       Json::array(
           {Json{{"orient", "bottom"},
                 {"scale", "x"},
                 {"labelAngle", -90},
                 {"labelAlign", "right"},
                 {"labelBaseline", "middle"},
                 {"labelFontSize", n > 40 ? 8 : 10},
                 {"labelOverlap", "parity"},
                 {"encode",
                  {{"labels", {{"update", {{"text", {{"signal", "names[datum.value]"}}}}}}}}}},
            Json{{"orient", "left"},
                 {"scale", "y"},
                 {"labelFontSize", n > 40 ? 8 : 10},
                 {"labelOverlap", "parity"},
                 {"encode",
                  {{"labels", {{"update", {{"text", {{"signal", "names[datum.value]"}}}}}}}}}}})},
      {"legends", Json::array({gradientLegend("colour", "correlation r", std::min(side, 240.0))})},
      {"marks",
       Json::array({Json{{"type", "rect"},
                         {"name", "cell-rects"},
                         {"from", {{"data", "cells"}}},
                         {"encode",
                          {{"enter",
                            {{"x", channel("x", "j")},
                             {"width", {{"scale", "x"}, {"band", 1}}},
                             {"y", channel("y", "i")},
                             {"height", {{"scale", "y"}, {"band", 1}}},
                             {"fill", channel("colour", "r")},
                             {"tooltip",
                              {{"signal",
                                "{'parameters': names[datum.i] + ' / ' + names[datum.j], 'r': "
                                "format(datum.r, '.3f')}"}}}}}}}}})}};
}

}  // namespace volcomp::report::charts
