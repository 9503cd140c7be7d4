#pragma once
// Building blocks of the report page: escaping and number formatting, tables, and the Page that
// collects sections and charts (each chart's Vega spec goes into a JSON script element that
// report.js draws) and writes the document.

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace volcomp::report::detail {

/// Text for HTML element content and attribute values.
std::string escape(std::string_view text);

/// `value` with `decimals` decimals and a true minus sign (−), e.g. "−3.20".
std::string fixed(double value, int decimals);
/// Decimals that show `value` to about `significant` significant digits (0 to 6).
int decimalsFor(double value, int significant = 3);
/// Value rounded like its uncertainty: sigma to two significant digits, value to the same
/// decimal place (GUM 7.2.6). Returns {value text, sigma text}.
std::pair<std::string, std::string> withUncertainty(double value, double sigma);

struct Cell {
  std::string html;
  bool numeric = false;
  std::string cssClass;
};
Cell text(std::string_view plain);
Cell number(double value, int decimals, std::string_view unit = {});
Cell numberHtml(std::string html);

class Table {
 public:
  explicit Table(std::vector<Cell> header, std::string caption = {});
  void row(std::vector<Cell> cells);
  bool empty() const noexcept { return rows_.empty(); }
  std::string html() const;

 private:
  std::vector<Cell> header_;
  std::string caption_;
  std::vector<std::vector<Cell>> rows_;
};

/// A paragraph, or a highlighted note.
std::string paragraph(std::string_view html, std::string_view cssClass = {});
std::string note(std::string_view html);

class Page {
 public:
  /// A <figure> holding a chart drawn from `spec`, with its caption (HTML). `id` must be unique
  /// in the page (it names the chart in tests and screenshots).
  std::string chart(const std::string& id, const nlohmann::json& spec, std::string_view caption);

  /// Adds a numbered section; `subsections` (id, title) appear in the table of contents.
  void section(const std::string& id, const std::string& title, std::string body,
               std::vector<std::pair<std::string, std::string>> subsections = {});

  int charts() const noexcept { return charts_; }
  const std::vector<std::pair<std::string, std::string>>& sectionList() const noexcept {
    return titles_;
  }

  /// The whole document: head with the stylesheet, `header` and `summary` (HTML) above the table
  /// of contents, the sections, `footer`, the chart specs and the scripts.
  std::string document(const std::string& title, const std::string& header,
                       const std::string& summary, const std::string& footer) const;

 private:
  struct Section {
    std::string id, title, body;
    std::vector<std::pair<std::string, std::string>> subsections;
  };
  std::vector<Section> sections_;
  std::vector<std::pair<std::string, std::string>> titles_;
  std::string specs_;
  int charts_ = 0;
};

}  // namespace volcomp::report::detail
