// Charts of an ISO 230-2 evaluation and of a compensation run.

#include <algorithm>
#include <cmath>

#include "chart_parts.hpp"
#include "charts.hpp"

namespace volcomp::report::charts {
namespace {

constexpr const char* kUp = "x̄↑ (approach in +)";
constexpr const char* kDown = "x̄↓ (approach in −)";
constexpr const char* kMean = "x̄ (bidirectional)";
constexpr const char* kUpColour = "#1f6fb4";
constexpr const char* kDownColour = "#d1495b";
constexpr const char* kMeanColour = "#59636e";

Json optionalValue(const std::optional<double>& value) {
  return value ? rounded(*value, 1e-5) : Json(nullptr);
}

// value ± 2 s, when both are present.
Json bandEdge(const std::optional<double>& mean, const std::optional<double>& s, double sign) {
  if (!mean || !s) return nullptr;
  return rounded(*mean + sign * 2.0 * *s, 1e-5);
}

Json bandMark(const std::string& name, const char* lo, const char* hi, const char* colour) {
  return Json{{"type", "area"},
              {"name", name},
              {"from", {{"data", "targets"}}},
              {"encode",
               {{"enter",
                 {{"x", channel("x", "p")},
                  {"y", channel("y", lo)},
                  {"y2", channel("y", hi)},
                  {"defined", {{"signal", std::string("isValid(datum.") + lo + ")"}}},
                  {"fill", {{"value", colour}}},
                  {"fillOpacity", {{"value", 0.14}}}}}}}};
}

}  // namespace

Json isoChart(const IsoAxis& evaluated) {
  Json targets = Json::array(), lines = Json::array(), runs = Json::array();
  std::vector<const IsoTarget*> sorted;
  for (const IsoTarget& t : evaluated.targets) sorted.push_back(&t);
  std::sort(sorted.begin(), sorted.end(),
            [](const IsoTarget* a, const IsoTarget* b) { return a->positionMm < b->positionMm; });
  bool anyUp = false, anyDown = false, anyMean = false;
  for (const IsoTarget* t : sorted) {
    const double p = t->positionMm;
    targets.push_back({{"p", p},
                       {"upLo", bandEdge(t->meanUp, t->sUp, -1)},
                       {"upHi", bandEdge(t->meanUp, t->sUp, +1)},
                       {"downLo", bandEdge(t->meanDown, t->sDown, -1)},
                       {"downHi", bandEdge(t->meanDown, t->sDown, +1)}});
    const auto line = [&](const std::optional<double>& v, const char* series, bool& any) {
      if (!v) return;
      any = true;
      lines.push_back({{"p", p}, {"s", series}, {"v", optionalValue(v)}});
    };
    line(t->meanUp, kUp, anyUp);
    line(t->meanDown, kDown, anyDown);
    line(t->mean, kMean, anyMean);
    for (double v : t->runsUp) runs.push_back({{"p", p}, {"s", kUp}, {"v", rounded(v, 1e-5)}});
    for (double v : t->runsDown) runs.push_back({{"p", p}, {"s", kDown}, {"v", rounded(v, 1e-5)}});
  }
  Json series = Json::array(), colours = Json::array(), dashes = Json::array();
  const auto add = [&](bool any, const char* name, const char* colour, Json dash) {
    if (!any) return;
    series.push_back(name);
    colours.push_back(colour);
    dashes.push_back(std::move(dash));
  };
  add(anyUp, kUp, kUpColour, Json::array({1, 0}));
  add(anyDown, kDown, kDownColour, Json::array({1, 0}));
  add(anyMean, kMean, kMeanColour, Json::array({5, 3}));
  const std::string tooltip =
      "{'series': datum.s, 'target': format(datum.p, '.1f') + ' mm', 'deviation': "
      "format(datum.v, '.2f') + ' µm'}";
  Json y = linearScale("y",
                       dataDomain({{"lines", "v"},
                                   {"runs", "v"},
                                   {"targets", "upLo"},
                                   {"targets", "upHi"},
                                   {"targets", "downLo"},
                                   {"targets", "downHi"}}),
                       "height");
  y["zero"] = true;
  y["nice"] = true;
  const std::string a = evaluated.axis ? axisName(*evaluated.axis) : "axis";
  return Json{
      {"width", 820},
      {"height", 260},
      {"padding", 4},
      {"autosize", "pad"},
      {"data", Json::array({Json{{"name", "targets"}, {"values", targets}},
                            Json{{"name", "lines"}, {"values", lines}},
                            Json{{"name", "runs"}, {"values", runs}}})},
      {"scales", Json::array({linearScale("x", dataDomain({{"targets", "p"}}), "width"), y,
                              ordinalScale("colour", series, colours),
                              ordinalScale("dash", series, dashes)})},
      {"axes", Json::array({axis("bottom", "x", "target position " + a + " (mm)"),
                            gridAxis("left", "y", "positional deviation (µm)")})},
      {"legends", Json::array({lineLegend(true)})},
      {"marks",
       Json::array(
           {zeroRule("y"), bandMark("band-up", "upLo", "upHi", kUpColour),
            bandMark("band-down", "downLo", "downHi", kDownColour),
            Json{{"type", "symbol"},
                 {"name", "run-points"},
                 {"from", {{"data", "runs"}}},
                 {"encode",
                  {{"enter",
                    {{"x", channel("x", "p")},
                     {"y", channel("y", "v")},
                     {"size", {{"value", 12}}},
                     {"stroke", channel("colour", "s")},
                     {"strokeOpacity", {{"value", 0.6}}},
                     {"strokeWidth", {{"value", 0.8}}},
                     {"tooltip", {{"signal", tooltip}}}}}}}},
            seriesLines("lines", "s", "p", "v", "means", true,
                        Json::array({Json{{"type", "symbol"},
                                          {"name", "mean-points"},
                                          {"from", {{"data", "series"}}},
                                          {"encode",
                                           {{"enter",
                                             {{"x", channel("x", "p")},
                                              {"y", channel("y", "v")},
                                              {"size", {{"value", 22}}},
                                              {"fill", channel("colour", "s")},
                                              {"tooltip", {{"signal", tooltip}}}}}}}}}))})}};
}

Json runBarChart(const RunSummary& run) {
  Json rows = Json::array();
  const auto add = [&](const std::string& axisLabel, const ErrorStats& stats) {
    if (stats.rmsBefore) {
      rows.push_back({{"a", axisLabel},
                      {"w", "without compensation"},
                      {"v", rounded(*stats.rmsBefore, 1e-4)}});
    }
    if (stats.rmsAfter) {
      rows.push_back(
          {{"a", axisLabel}, {"w", "with compensation"}, {"v", rounded(*stats.rmsAfter, 1e-4)}});
    }
  };
  const char* names[3] = {"X", "Y", "Z"};
  for (std::size_t k = 0; k < 3; ++k) add(names[k], run.axes[k]);
  add("|e| (3-D)", run.total);
  return Json{
      {"width", 420},
      {"height", 200},
      {"padding", 4},
      {"autosize", "pad"},
      {"data", Json::array({Json{{"name", "rms"}, {"values", rows}}})},
      {"scales",
       Json::array(
           {Json{{"name", "x"},
                 {"type", "band"},
                 {"domain", {{"data", "rms"}, {"field", "a"}}},
                 {"range", "width"},
                 {"padding", 0.25}},
            Json{{"name", "y"},
                 {"type", "linear"},
                 {"domain", {{"data", "rms"}, {"field", "v"}}},
                 {"range", "height"},
                 {"zero", true},
                 {"nice", true}},
            ordinalScale("colour", Json::array({"without compensation", "with compensation"}),
                         Json::array({"#9aa4ae", "#1a7f37"}))})},
      {"axes", Json::array({axis("bottom", "x", "error direction"),
                            gridAxis("left", "y", "RMS tool-tip error (µm)")})},
      {"legends", Json::array({swatchLegend("colour")})},
      {"marks",
       Json::array({Json{
           {"type", "group"},
           {"from", {{"facet", {{"name", "pair"}, {"data", "rms"}, {"groupby", "a"}}}}},
           {"encode",
            {{"enter", {{"x", channel("x", "a")}, {"width", {{"scale", "x"}, {"band", 1}}}}}}},
           {"signals", Json::array({Json{{"name", "width"}, {"update", "bandwidth('x')"}}})},
           {"scales", Json::array({Json{{"name", "pos"},
                                        {"type", "band"},
                                        {"domain", {{"data", "pair"}, {"field", "w"}}},
                                        {"range", "width"},
                                        {"padding", 0.08}}})},
           {"marks",
            Json::array({Json{{"type", "rect"},
                              {"name", "bars"},
                              {"from", {{"data", "pair"}}},
                              {"encode",
                               {{"enter",
                                 {{"x", channel("pos", "w")},
                                  {"width", {{"scale", "pos"}, {"band", 1}}},
                                  {"y", channel("y", "v")},
                                  {"y2", {{"scale", "y"}, {"value", 0}}},
                                  {"fill", channel("colour", "w")},
                                  {"tooltip",
                                   {{"signal",
                                     "{'': datum.w, 'RMS': format(datum.v, '.2f') + ' µm'}"}}}}}}}},
                         Json{{"type", "text"},
                              {"name", "values"},
                              {"from", {{"data", "pair"}}},
                              {"encode",
                               {{"enter",
                                 {{"x", {{"scale", "pos"}, {"field", "w"}, {"band", 0.5}}},
                                  {"y", {{"scale", "y"}, {"field", "v"}, {"offset", -4}}},
                                  {"align", {{"value", "center"}}},
                                  {"baseline", {{"value", "bottom"}}},
                                  {"text", {{"signal", "format(datum.v, '.2f')"}}}}}}}}})}}})}};
}

Json offsetsChart(std::span<const RecordedWrite> writes) {
  // At most about 1500 writes per axis on the page: every k-th, the violations always.
  const std::size_t step = std::max<std::size_t>(1, writes.size() / 1500);
  Json t = Json::array(), violations = Json::array();
  std::array<Json, 3> offsets{Json::array(), Json::array(), Json::array()};
  for (std::size_t i = 0; i < writes.size(); ++i) {
    const RecordedWrite& w = writes[i];
    if (i % step == 0 || i + 1 == writes.size()) {
      t.push_back(rounded(w.tS, 1e-4));
      for (std::size_t k = 0; k < 3; ++k) {
        offsets[k].push_back(rounded(w.offsetMm[k] * kUmPerMm, 1e-3));
      }
    }
    if (w.violation) violations.push_back({{"t", rounded(w.tS, 1e-4)}});
  }
  Json spec{
      {"width", 820},
      {"height", 200},
      {"padding", 4},
      {"autosize", "pad"},
      {"scales",
       Json::array({linearScale("x", dataDomain({{"writes", "t"}}), "width"),
                    [] {
                      Json y = linearScale("y", dataDomain({{"writes", "o"}}), "height");
                      y["nice"] = true;
                      y["zero"] = true;
                      return y;
                    }(),
                    ordinalScale("colour", Json::array({"X", "Y", "Z"}),
                                 Json::array({axisColour(0), axisColour(1), axisColour(2)}))})},
      {"axes", Json::array({axis("bottom", "x", "time (s)"),
                            gridAxis("left", "y", "offset written (µm)")})},
      {"legends", Json::array({lineLegend(false)})},
      {"marks", Json::array({zeroRule("y"),
                             Json{{"type", "rule"},
                                  {"name", "violation-rules"},
                                  {"from", {{"data", "violations"}}},
                                  {"encode",
                                   {{"enter",
                                     {{"x", channel("x", "t")},
                                      {"y", {{"value", 0}}},
                                      {"y2", {{"signal", "height"}}},
                                      {"stroke", {{"value", "#cf222e"}}}}}}}},
                             seriesLines("writes", "a", "t", "o", "offsets", false)})}};
  // One row per write and axis: (t, X, Y, Z) folded into (t, a, o).
  const std::size_t rows = t.size();
  addColumns(spec, "writes", rows,
             {{"t", std::move(t)}, {"X", offsets[0]}, {"Y", offsets[1]}, {"Z", offsets[2]}},
             Json::array({Json{{"type", "fold"},
                               {"fields", Json::array({"X", "Y", "Z"})},
                               {"as", Json::array({"a", "o"})}}}));
  spec["data"].push_back(Json{{"name", "violations"}, {"values", violations}});
  return spec;
}

}  // namespace volcomp::report::charts
