#pragma once
// Small pieces of Vega specifications used by every chart builder.

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace volcomp::report::charts {

using Json = nlohmann::json;

/// {"name", "type": "linear", "domain", "range", "zero": false, "nice": false}.
Json linearScale(const std::string& name, Json domain, const std::string& range);
/// {"name", "type": "ordinal", "domain", "range"} with explicit lists.
Json ordinalScale(const std::string& name, Json domain, Json range);
/// A domain over fields of data sets: {"fields": [{"data", "field"}, ...]}.
Json dataDomain(std::initializer_list<std::pair<const char*, const char*>> fields);
/// An axis with a title; gridAxis adds grid lines and asks for about 6 ticks.
Json axis(const std::string& orient, const std::string& scale, const std::string& title);
Json gridAxis(const std::string& orient, const std::string& scale, const std::string& title);
/// {"scale": scale, "field": field}: a channel encoded from a data field.
Json channel(const std::string& scale, const std::string& field);
/// One line per value of `by` in data set `data` (a facet), x and y from those fields, stroked by
/// the "colour" scale and, when `dashed`, dashed by the "dash" scale; `name` names the line mark.
/// `more` are further marks drawn in each group over the group's data "series".
Json seriesLines(const std::string& data, const std::string& by, const std::string& x,
                 const std::string& y, const std::string& name, bool dashed,
                 Json more = Json::array());
/// A thin horizontal rule at value 0 of the y scale `scale`.
Json zeroRule(const std::string& scale);
/// A colour-gradient legend to the right of the plot, as long as the plot is high.
Json gradientLegend(const std::string& scale, const std::string& title, double plotHeight);
/// A legend of line samples above the plot for the "colour" (and, when `dashed`, "dash") scale.
Json lineLegend(bool dashed);
/// A legend of coloured squares for an ordinal fill scale, above the plot.
Json swatchLegend(const std::string& scale);
/// Adds to `spec` a data set `name` whose `rows` rows Vega builds from columns: `columns` holds
/// one array of `rows` values per field, kept in one signal. Rows as objects would repeat every
/// key in every row; columns hold each key once (a third of the size for numeric tables).
/// `transforms` are appended after the columns became fields (e.g. formulas, a fold).
void addColumns(Json& spec, const std::string& name, std::size_t rows,
                const std::vector<std::pair<std::string, Json>>& columns,
                Json transforms = Json::array());

/// Short text for a chart label: `value` with the decimals it needs (up to 3 significant).
std::string label(double value);

}  // namespace volcomp::report::charts
