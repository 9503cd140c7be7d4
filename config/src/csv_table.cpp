#include "volcomp/config/csv_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "volcomp/config/model_file.hpp"
#include "volcomp/config/printable.hpp"

namespace volcomp::config {
namespace {

std::string_view trimmed(std::string_view text) noexcept {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::string lower(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

std::string lineKey(std::size_t line) {
  return "line " + std::to_string(line);
}

// Spreadsheets and instrument software write the micro sign; the format's names are ASCII.
std::string asciiUnit(std::string unit) {
  for (const char* micro : {"\xC2\xB5", "\xCE\xBC"}) {  // U+00B5 and U+03BC
    if (unit.rfind(micro, 0) == 0) unit = "u" + unit.substr(2);
  }
  return unit;
}

std::string expectedColumns(const CsvSchema& schema) {
  std::string required, optional;
  for (const CsvColumn& c : schema.columns) {
    std::string& list = c.required ? required : optional;
    list += (list.empty() ? "" : ",") + c.name;
  }
  std::string text = "expected " + required;
  if (!optional.empty()) text += " and optionally " + optional;
  if (!schema.ignored.empty()) {
    std::string ignored;
    for (const std::string& name : schema.ignored) ignored += (ignored.empty() ? "" : ",") + name;
    text += "; " + ignored + " are accepted and ignored";
  }
  return text + "; a unit suffix such as _mm or _um may follow a name";
}

}  // namespace

CsvSchema& CsvSchema::add(std::initializer_list<const char*> names, CsvQuantity quantity,
                          bool required) {
  for (const char* name : names) columns.push_back({name, quantity, required});
  return *this;
}

CsvSchema& CsvSchema::addGroup(std::initializer_list<const char*> names, CsvQuantity quantity) {
  add(names, quantity, false);
  groups.emplace_back(names.begin(), names.end());
  return *this;
}

CsvSchema& CsvSchema::ignore(std::initializer_list<const char*> names) {
  ignored.insert(ignored.end(), names.begin(), names.end());
  return *this;
}

bool parseDirectionsText(std::string_view text, model::Directions& directions) noexcept {
  std::size_t axis = 0;
  for (char c : text) {
    if (c == ' ' || c == ',' || c == ';' || c == '/' || c == '\t') continue;
    if (axis == 3) return false;
    if (c == '+') {
      directions[axis++] = model::Direction::Positive;
    } else if (c == '-') {
      directions[axis++] = model::Direction::Negative;
    } else if (c == '0' || c == '?') {
      directions[axis++] = model::Direction::Unknown;
    } else {
      return false;
    }
  }
  return axis == 3;
}

CsvSchema positionsSchema() {
  CsvSchema schema;
  schema.add({"x", "y", "z"}, CsvQuantity::Length, true)
      .addGroup({"tx", "ty", "tz"}, CsvQuantity::Length)
      .add({"direction"}, CsvQuantity::Direction);
  return schema;
}

std::ifstream CsvReader::open(const std::string& path) {
  return openTextFile(path);
}

CsvReader::CsvReader(std::istream& input, std::string file, CsvSchema schema)
    : lines_(input, file), file_(std::move(file)), schema_(std::move(schema)) {
  readHeader();
}

bool CsvReader::readLine() {
  std::string_view line;
  while (lines_.next(line)) {
    line_ = lines_.lineNumber();
    if (line_ == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    const std::string_view content = trimmed(line);
    if (content.empty() || content.front() == '#') continue;
    text_.assign(line);  // the fields are views into text_
    return true;
  }
  return false;
}

void CsvReader::splitCurrent() {
  fields_.clear();
  unquoted_.clear();
  const std::string_view line(text_);
  // Views into unquoted_ must stay valid while it grows: room for as many fields as the line
  // could hold (only lines with quotes pay for it).
  if (line.find('"') != std::string_view::npos) unquoted_.reserve(line.size() + 1);
  std::size_t start = 0;
  while (true) {
    std::size_t cursor = start;
    while (cursor < line.size() && (line[cursor] == ' ' || line[cursor] == '\t')) ++cursor;
    if (cursor < line.size() && line[cursor] == '"') {
      std::string value;
      ++cursor;
      while (true) {
        if (cursor >= line.size()) fail("a quoted field is not closed");
        if (line[cursor] == '"') {
          if (cursor + 1 < line.size() && line[cursor + 1] == '"') {
            value += '"';
            cursor += 2;
            continue;
          }
          ++cursor;
          break;
        }
        value += line[cursor++];
      }
      const std::size_t comma = line.find(',', cursor);
      if (!trimmed(line.substr(cursor, comma - cursor)).empty()) {
        fail("unexpected text after a quoted field");
      }
      unquoted_.push_back(std::move(value));
      fields_.push_back(unquoted_.back());
      if (comma == std::string_view::npos) break;
      start = comma + 1;
      continue;
    }
    const std::size_t comma = line.find(',', start);
    fields_.push_back(trimmed(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

void CsvReader::readHeader() {
  const std::string expected = expectedColumns(schema_);
  if (!readLine())
    throw ConfigError(file_, "", "empty file: expected a header line (" + expected + ")");
  splitCurrent();
  columnOfSchema_.assign(schema_.columns.size(), -1);
  std::vector<std::string> seen;
  for (std::size_t c = 0; c < fields_.size(); ++c) {
    const std::string written(fields_[c]);
    const std::string name = lower(written);
    Bound bound;
    bound.written = written;
    std::string base = name, unit;
    // Known names take precedence over a suffix reading (no schema name holds '_' today, but a
    // future one might).
    const auto known = [&](const std::string& candidate) {
      for (std::size_t s = 0; s < schema_.columns.size(); ++s) {
        if (schema_.columns[s].name == candidate) return static_cast<int>(s);
      }
      return -1;
    };
    int index = known(name);
    const bool ignored =
        std::find(schema_.ignored.begin(), schema_.ignored.end(), name) != schema_.ignored.end();
    if (index < 0 && !ignored) {
      const auto underscore = name.rfind('_');
      if (underscore != std::string::npos) {
        base = name.substr(0, underscore);
        unit = asciiUnit(name.substr(underscore + 1));
        index = known(base);
      }
    }
    const bool ignoredBase =
        std::find(schema_.ignored.begin(), schema_.ignored.end(), base) != schema_.ignored.end();
    if (index < 0 && !ignored && !ignoredBase) {
      throw ConfigError(file_, lineKey(line_),
                        "unknown column " + config::quoted(written) + " (" + expected + ")");
    }
    if (std::find(seen.begin(), seen.end(), base) != seen.end()) {
      throw ConfigError(file_, lineKey(line_), "column " + config::quoted(base) + " appears twice");
    }
    seen.push_back(base);
    if (index >= 0) {
      const CsvColumn& column = schema_.columns[static_cast<std::size_t>(index)];
      const std::string where = lineKey(line_) + ", column " + written;
      if (!unit.empty()) {
        switch (column.quantity) {
          case CsvQuantity::Length:
            bound.factor = lengthUnitToMm(unit, file_, where);
            break;
          case CsvQuantity::Angle:
            bound.factor = angleUnitToRad(unit, file_, where);
            break;
          case CsvQuantity::Number:
          case CsvQuantity::Direction:
            throw ConfigError(file_, where, "column \"" + base + "\" takes no unit suffix");
        }
      }
      bound.schemaIndex = index;
      columnOfSchema_[static_cast<std::size_t>(index)] = static_cast<int>(c);
    }
    header_.push_back(std::move(bound));
  }
  for (std::size_t s = 0; s < schema_.columns.size(); ++s) {
    if (schema_.columns[s].required && columnOfSchema_[s] < 0) {
      throw ConfigError(file_, lineKey(line_),
                        "missing column \"" + schema_.columns[s].name + "\" (" + expected + ")");
    }
  }
  for (const std::vector<std::string>& group : schema_.groups) {
    std::size_t present = 0;
    std::string names;
    for (const std::string& name : group) {
      present += has(name) ? 1 : 0;
      names += (names.empty() ? "" : ",") + name;
    }
    if (present != 0 && present != group.size()) {
      throw ConfigError(file_, lineKey(line_), "give all of " + names + " or none");
    }
  }
}

int CsvReader::column(std::string_view name) const noexcept {
  for (std::size_t s = 0; s < schema_.columns.size(); ++s) {
    if (schema_.columns[s].name == name) return columnOfSchema_[s];
  }
  return -1;
}

int CsvReader::requiredColumn(std::string_view name) const {
  const int c = column(name);
  if (c < 0) throw ConfigError(file_, lineKey(line_), "no column \"" + std::string(name) + "\"");
  return c;
}

const std::string& CsvReader::headerName(int column) const {
  return header_.at(static_cast<std::size_t>(column)).written;
}

std::string CsvReader::headerText() const {
  std::string text;
  for (const Bound& b : header_) text += (text.empty() ? "" : ",") + b.written;
  return text;
}

bool CsvReader::next() {
  if (!readLine()) return false;
  splitCurrent();
  if (fields_.size() != header_.size()) {
    fail("expected " + std::to_string(header_.size()) + " fields (" + headerText() + "), got " +
         std::to_string(fields_.size()));
  }
  return true;
}

std::string_view CsvReader::field(int column) const {
  return fields_.at(static_cast<std::size_t>(column));
}

double CsvReader::number(int column) const {
  const std::string_view text = field(column);
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;
  double value = 0.0;
  const auto [pointer, error] = std::from_chars(begin, end, value);
  if (text.empty() || error != std::errc() || pointer != end || !std::isfinite(value)) {
    fail(column, "expected a finite number, got " + config::quoted(text));
  }
  return value * header_[static_cast<std::size_t>(column)].factor;
}

model::Directions CsvReader::directions(int column) const {
  model::Directions directions{};
  if (!parseDirectionsText(field(column), directions)) {
    fail(column, "expected one direction per axis X, Y, Z (+, - or 0), such as +-+, got " +
                     config::quoted(field(column)));
  }
  return directions;
}

void CsvReader::fail(int column, const std::string& message) const {
  throw ConfigError(file_, lineKey(line_) + ", column " + headerName(column), message);
}

void CsvReader::fail(const std::string& message) const {
  throw ConfigError(file_, lineKey(line_), message);
}

}  // namespace volcomp::config
