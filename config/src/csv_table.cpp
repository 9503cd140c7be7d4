#include "volcomp/config/csv_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

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

// The units CSV files from instruments and spreadsheets carry, beyond the model file's mm, um, nm.
std::optional<double> csvLengthUnitToMm(const std::string& unit) {
  if (unit == "micron" || unit == "microns") return 1e-3;
  if (unit == "m") return 1e3;
  if (unit == "in" || unit == "inch") return 25.4;
  return lengthUnitFactor(unit);
}

struct HeaderName {
  std::string name;  ///< lower case, blanks and hyphens as '_'
  std::string unit;  ///< from "name [unit]" or "name (unit)", µ as u; empty otherwise
};

std::string normalisedName(std::string_view text) {
  std::string name = lower(trimmed(text));
  for (char& c : name) {
    if (c == ' ' || c == '\t' || c == '-') c = '_';
  }
  while (!name.empty() && (name.back() == '_' || name.back() == '/')) name.pop_back();
  return name;
}

HeaderName splitHeaderName(std::string_view written) {
  const std::string_view text = trimmed(written);
  const char close = text.empty() ? '\0' : text.back();
  if (close == ']' || close == ')') {
    const std::size_t open = text.rfind(close == ']' ? '[' : '(');
    if (open != std::string_view::npos) {
      return {normalisedName(text.substr(0, open)),
              asciiUnit(lower(trimmed(text.substr(open + 1, text.size() - open - 2))))};
    }
  }
  return {normalisedName(text), {}};
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
  for (const char* name : names) columns.push_back({name, quantity, required, {}});
  return *this;
}

CsvSchema& CsvSchema::addGroup(std::initializer_list<const char*> names, CsvQuantity quantity) {
  add(names, quantity, false);
  groups.emplace_back(names.begin(), names.end());
  return *this;
}

CsvSchema& CsvSchema::alias(const char* name, std::initializer_list<const char*> aliases) {
  for (CsvColumn& column : columns) {
    if (column.name == name)
      column.aliases.insert(column.aliases.end(), aliases.begin(), aliases.end());
  }
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
      const std::size_t comma = line.find(delimiter_, cursor);
      if (!trimmed(line.substr(cursor, comma - cursor)).empty()) {
        fail("unexpected text after a quoted field");
      }
      unquoted_.push_back(std::move(value));
      fields_.push_back(unquoted_.back());
      if (comma == std::string_view::npos) break;
      start = comma + 1;
      continue;
    }
    const std::size_t comma = line.find(delimiter_, start);
    fields_.push_back(trimmed(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

void CsvReader::bindHeaderField(std::size_t column, std::vector<std::string>& seen) {
  Bound bound;
  bound.written = std::string(fields_[column]);
  const HeaderName header = splitHeaderName(bound.written);
  const auto known = [&](const std::string& name) {
    for (std::size_t s = 0; s < schema_.columns.size(); ++s) {
      const CsvColumn& candidate = schema_.columns[s];
      if (candidate.name == name || std::find(candidate.aliases.begin(), candidate.aliases.end(),
                                              name) != candidate.aliases.end()) {
        return static_cast<int>(s);
      }
    }
    return -1;
  };
  const auto ignored = [&](const std::string& name) {
    return std::find(schema_.ignored.begin(), schema_.ignored.end(), name) != schema_.ignored.end();
  };
  // A whole name the schema knows takes precedence over reading its end as a unit suffix.
  std::string base = header.name, unit = header.unit;
  bool suffix = false;
  int index = known(base);
  if (index < 0 && !ignored(base) && unit.empty()) {
    const auto cut = base.find_last_of("_/");
    if (cut != std::string::npos) {
      unit = asciiUnit(base.substr(cut + 1));
      base.resize(cut);
      suffix = true;
      index = known(base);
    }
  }
  const std::string where = lineKey(line_) + ", column " + bound.written;
  const auto other = [&] {
    if (!schema_.acceptOtherColumns) {
      throw ConfigError(file_, lineKey(line_),
                        "unknown column " + config::quoted(bound.written) + " (" +
                            expectedColumns(schema_) + ")");
    }
    if (!bound.written.empty()) other_.push_back(bound.written);
    header_.push_back(std::move(bound));
  };
  if (index < 0 && !ignored(base)) return other();
  if (index >= 0) {
    const CsvColumn& schemaColumn = schema_.columns[static_cast<std::size_t>(index)];
    std::optional<double> factor = 1.0;
    if (unit.empty()) {
      if (schemaColumn.quantity == CsvQuantity::Length && schema_.lengthUnitRequired) {
        throw ConfigError(file_, where,
                          "a length column needs its unit in the header, e.g. \"" +
                              schemaColumn.name + "_mm\" (units: nm, um, mm, m, in)");
      }
    } else if (schemaColumn.quantity == CsvQuantity::Length) {
      factor = csvLengthUnitToMm(unit);
    } else if (schemaColumn.quantity == CsvQuantity::Angle) {
      factor = angleUnitFactor(unit);
    } else {
      factor = std::nullopt;
    }
    // With other columns accepted, a name with an unknown suffix (temp_c) is another column.
    if (!factor && suffix && schema_.acceptOtherColumns) return other();
    if (!factor) {
      switch (schemaColumn.quantity) {
        case CsvQuantity::Length:
          throw ConfigError(file_, where,
                            "expected a length unit \"mm\", \"um\", \"nm\", \"m\" or \"in\", got " +
                                config::quoted(unit));
        case CsvQuantity::Angle:
          angleUnitToRad(unit, file_, where);  // throws, naming the units
          break;
        case CsvQuantity::Number:
        case CsvQuantity::Direction:
        case CsvQuantity::Text:
          break;
      }
      throw ConfigError(file_, where, "column \"" + schemaColumn.name + "\" takes no unit suffix");
    }
    base = schemaColumn.name;
    bound.factor = *factor;
    bound.schemaIndex = index;
    columnOfSchema_[static_cast<std::size_t>(index)] = static_cast<int>(column);
  }
  if (std::find(seen.begin(), seen.end(), base) != seen.end()) {
    throw ConfigError(file_, lineKey(line_), "column " + config::quoted(base) + " appears twice");
  }
  seen.push_back(base);
  header_.push_back(std::move(bound));
}

void CsvReader::readHeader() {
  if (!readLine()) {
    throw CsvNoHeader(file_, "",
                      "empty file: expected a header line (" + expectedColumns(schema_) + ")");
  }
  // Semicolon-separated exports come from locales that write a decimal comma.
  const std::string_view header(text_);
  if (header.find(';') != std::string_view::npos && header.find(',') == std::string_view::npos) {
    delimiter_ = ';';
    decimalComma_ = true;
  }
  splitCurrent();
  columnOfSchema_.assign(schema_.columns.size(), -1);
  std::vector<std::string> seen;
  for (std::size_t c = 0; c < fields_.size(); ++c) bindHeaderField(c, seen);
  const std::string expected = expectedColumns(schema_);
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
  for (const Bound& b : header_) {
    if (!text.empty()) text += delimiter_;
    text += b.written;
  }
  return text;
}

bool CsvReader::next() {
  if (!readLine()) return false;
  splitCurrent();
  if (fields_.size() < header_.size() ||
      (fields_.size() > header_.size() && !schema_.acceptOtherColumns)) {
    fail("expected " + std::to_string(header_.size()) + " fields (" + headerText() + "), got " +
         std::to_string(fields_.size()));
  }
  return true;
}

std::string_view CsvReader::field(int column) const {
  return fields_.at(static_cast<std::size_t>(column));
}

double CsvReader::number(int column) const {
  std::string_view text = field(column);
  std::string pointed;
  if (decimalComma_ && text.find(',') != std::string_view::npos) {
    pointed.assign(text);
    std::replace(pointed.begin(), pointed.end(), ',', '.');
    text = pointed;
  }
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;
  double value = 0.0;
  const auto [pointer, error] = std::from_chars(begin, end, value);
  if (text.empty() || error != std::errc() || pointer != end || !std::isfinite(value)) {
    fail(column, "expected a finite number, got " + config::quoted(field(column)));
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
