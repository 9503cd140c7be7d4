#include "page.hpp"

#include <algorithm>
#include <cmath>

#include "volcomp/format/numbers.hpp"
#include "volcomp/report/assets.hpp"

namespace volcomp::report::detail {

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return "–";
  // No "−0.00": the sign is shown only when the printed digits are not all zero.
  const std::string digits = format::fixed(std::abs(value), std::clamp(decimals, 0, 9));
  const bool zero = digits.find_first_not_of("0.") == std::string::npos;
  return (value < 0 && !zero ? "−" : "") + digits;
}

int decimalsFor(double value, int significant) {
  if (!std::isfinite(value) || value == 0.0) return 0;
  const int exponent = static_cast<int>(std::floor(std::log10(std::abs(value))));
  return std::clamp(significant - 1 - exponent, 0, 6);
}

std::pair<std::string, std::string> withUncertainty(double value, double sigma) {
  if (!std::isfinite(sigma) || sigma <= 0.0) return {fixed(value, decimalsFor(value, 4)), "–"};
  const int decimals = std::clamp(1 - static_cast<int>(std::floor(std::log10(sigma))), 0, 6);
  return {fixed(value, decimals), fixed(sigma, decimals)};
}

Cell text(std::string_view plain) {
  return Cell{escape(plain), false, {}};
}

Cell number(double value, int decimals, std::string_view unit) {
  std::string html = fixed(value, decimals);
  if (!unit.empty() && std::isfinite(value)) html += "&#8239;" + escape(unit);
  return Cell{html, true, {}};
}

Cell numberHtml(std::string html) {
  return Cell{std::move(html), true, {}};
}

Table::Table(std::vector<Cell> header, std::string caption)
    : header_(std::move(header)), caption_(std::move(caption)) {}

void Table::row(std::vector<Cell> cells) {
  rows_.push_back(std::move(cells));
}

namespace {

std::string cellTag(const char* tag, const Cell& cell) {
  std::string classes = cell.numeric ? "num" : "";
  if (!cell.cssClass.empty()) classes += (classes.empty() ? "" : " ") + cell.cssClass;
  std::string out = "<" + std::string(tag);
  if (!classes.empty()) out += " class=\"" + classes + "\"";
  return out + ">" + cell.html + "</" + tag + ">";
}

}  // namespace

std::string Table::html() const {
  std::string out = "<div class=\"table-wrap\"><table>";
  if (!caption_.empty()) out += "<caption>" + caption_ + "</caption>";
  out += "<thead><tr>";
  for (const Cell& cell : header_) out += cellTag("th", cell);
  out += "</tr></thead><tbody>";
  for (const auto& row : rows_) {
    out += "<tr>";
    for (const Cell& cell : row) out += cellTag("td", cell);
    out += "</tr>";
  }
  return out + "</tbody></table></div>\n";
}

std::string paragraph(std::string_view html, std::string_view cssClass) {
  std::string out = "<p";
  if (!cssClass.empty()) out += " class=\"" + std::string(cssClass) + "\"";
  return out + ">" + std::string(html) + "</p>\n";
}

std::string note(std::string_view html) {
  return "<div class=\"note\">" + std::string(html) + "</div>\n";
}

std::string Page::chart(const std::string& id, const nlohmann::json& spec,
                        std::string_view caption) {
  ++charts_;
  // '<' only occurs inside JSON strings; as \u003c no "</script" can end the element early.
  std::string json = spec.dump();
  std::string safe;
  safe.reserve(json.size());
  for (char c : json) {
    if (c == '<') {
      safe += "\\u003c";
    } else {
      safe += c;
    }
  }
  specs_ += "<script type=\"application/json\" id=\"spec-" + id + "\">" + safe + "</script>\n";
  return "<figure id=\"fig-" + id + "\"><div class=\"chart\" id=\"" + id + "\" data-spec=\"spec-" +
         id + "\"></div><figcaption>" + std::string(caption) + "</figcaption></figure>\n";
}

void Page::section(const std::string& id, const std::string& title, std::string body,
                   std::vector<std::pair<std::string, std::string>> subsections) {
  titles_.emplace_back(id, title);
  sections_.push_back({id, title, std::move(body), std::move(subsections)});
}

std::string Page::document(const std::string& title, const std::string& header,
                           const std::string& summary, const std::string& footer) const {
  std::string out;
  out.reserve(vegaRuntime().size() + specs_.size() + 200000);
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + escape(title) + "</title>\n<style>\n" + stylesheet() + "</style>\n";
  out += "</head>\n<body>\n<div class=\"page\">\n" + header + summary;
  out += "<nav class=\"toc\" aria-label=\"Contents\"><h2>Contents</h2><ol>\n";
  for (const Section& s : sections_) {
    out += "<li><a href=\"#" + s.id + "\">" + escape(s.title) + "</a>";
    if (!s.subsections.empty()) {
      out += "<ol>";
      for (const auto& [id, sub] : s.subsections) {
        out += "<li><a href=\"#" + id + "\">" + escape(sub) + "</a></li>";
      }
      out += "</ol>";
    }
    out += "</li>\n";
  }
  out += "</ol></nav>\n";
  int number = 0;
  for (const Section& s : sections_) {
    out += "<section class=\"report-section\" id=\"" + s.id + "\">\n<h2><span class=\"number\">" +
           std::to_string(++number) + "</span>" + escape(s.title) + "</h2>\n" + s.body +
           "</section>\n";
  }
  out += footer + "</div>\n" + specs_;
  out += "<script>\n" + vegaRuntime() + "\n</script>\n";
  out += "<script>\n" + reportScript() + "</script>\n</body>\n</html>\n";
  return out;
}

}  // namespace volcomp::report::detail
