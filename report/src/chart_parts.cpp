#include "chart_parts.hpp"

#include "page.hpp"

namespace volcomp::report::charts {

Json linearScale(const std::string& name, Json domain, const std::string& range) {
  return Json{{"name", name},   {"type", "linear"}, {"domain", std::move(domain)},
              {"range", range}, {"zero", false},    {"nice", false}};
}

Json ordinalScale(const std::string& name, Json domain, Json range) {
  return Json{{"name", name},
              {"type", "ordinal"},
              {"domain", std::move(domain)},
              {"range", std::move(range)}};
}

Json dataDomain(std::initializer_list<std::pair<const char*, const char*>> fields) {
  Json list = Json::array();
  for (const auto& [data, field] : fields) list.push_back(Json{{"data", data}, {"field", field}});
  return Json{{"fields", list}};
}

Json axis(const std::string& orient, const std::string& scale, const std::string& title) {
  return Json{{"orient", orient}, {"scale", scale}, {"title", title}, {"labelOverlap", true}};
}

Json gridAxis(const std::string& orient, const std::string& scale, const std::string& title) {
  Json a = axis(orient, scale, title);
  a["grid"] = true;
  a["tickCount"] = 6;
  return a;
}

Json channel(const std::string& scale, const std::string& field) {
  return Json{{"scale", scale}, {"field", field}};
}

Json seriesLines(const std::string& data, const std::string& by, const std::string& x,
                 const std::string& y, const std::string& name, bool dashed, Json more) {
  Json encode{{"x", channel("x", x)},
              {"y", channel("y", y)},
              {"stroke", channel("colour", by)},
              {"strokeWidth", {{"value", dashed ? 1.8 : 1.3}}}};
  if (dashed) encode["strokeDash"] = channel("dash", by);
  Json marks = Json::array({Json{{"type", "line"},
                                 {"name", name},
                                 {"from", {{"data", "series"}}},
                                 {"encode", {{"enter", std::move(encode)}}}}});
  for (Json& mark : more) marks.push_back(std::move(mark));
  return Json{{"type", "group"},
              {"from", {{"facet", {{"name", "series"}, {"data", data}, {"groupby", by}}}}},
              {"marks", std::move(marks)}};
}

Json zeroRule(const std::string& scale) {
  return Json{{"type", "rule"},
              {"name", "zero"},
              {"encode",
               {{"update",
                 {{"x", {{"value", 0}}},
                  {"x2", {{"signal", "width"}}},
                  {"y", {{"scale", scale}, {"value", 0}}},
                  {"stroke", {{"value", "#8c959f"}}},
                  {"strokeWidth", {{"value", 0.8}}}}}}}};
}

Json gradientLegend(const std::string& scale, const std::string& title, double plotHeight) {
  return Json{{"fill", scale},
              {"type", "gradient"},
              {"title", title},
              {"orient", "right"},
              {"gradientLength", std::max(60.0, plotHeight - 24.0)},
              {"gradientThickness", 12}};
}

Json lineLegend(bool dashed) {
  Json legend{{"stroke", "colour"},     {"orient", "top"},        {"direction", "horizontal"},
              {"symbolType", "stroke"}, {"symbolStrokeWidth", 2}, {"symbolSize", 220}};
  if (dashed) legend["strokeDash"] = "dash";
  return legend;
}

Json swatchLegend(const std::string& scale) {
  return Json{
      {"fill", scale}, {"orient", "top"}, {"direction", "horizontal"}, {"symbolType", "square"}};
}

void addColumns(Json& spec, const std::string& name, std::size_t rows,
                const std::vector<std::pair<std::string, Json>>& columns, Json transforms) {
  std::string signal = name + "_columns";
  for (char& c : signal) {
    if (c == '-') c = '_';
  }
  Json values = Json::object();
  Json steps =
      Json::array({Json{{"type", "sequence"}, {"start", 0}, {"stop", rows}, {"as", "row"}}});
  for (const auto& [field, column] : columns) {
    values[field] = column;
    steps.push_back(Json{
        {"type", "formula"}, {"expr", signal + "['" + field + "'][datum.row]"}, {"as", field}});
  }
  for (Json& step : transforms) steps.push_back(std::move(step));
  if (!spec.contains("signals")) spec["signals"] = Json::array();
  spec["signals"].push_back(Json{{"name", signal}, {"value", std::move(values)}});
  if (!spec.contains("data")) spec["data"] = Json::array();
  spec["data"].push_back(Json{{"name", name}, {"transform", std::move(steps)}});
}

std::string label(double value) {
  return detail::fixed(value, detail::decimalsFor(value, 3));
}

}  // namespace volcomp::report::charts
