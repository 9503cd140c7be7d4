#include "volcomp/config/json_reader.hpp"

#include <algorithm>
#include <cmath>

namespace volcomp::config {
namespace {

std::string joinChoices(const std::vector<std::string>& choices) {
  std::string out;
  for (const std::string& c : choices) {
    if (!out.empty()) out += ", ";
    out += c;
  }
  return out;
}

// Levenshtein distance: the edits (insert, delete, replace a byte) that turn `a` into `b`.
std::size_t keyEdits(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The allowed key a typo most likely meant: the fewest edits, at most a third of the key's
// length (and at least 2); empty when none is that close.
std::string closestKey(std::string_view unknown, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t bestEdits = std::max<std::size_t>(2, unknown.size() / 3) + 1;
  for (const std::string& a : allowed) {
    const std::size_t edits = keyEdits(unknown, a);
    if (edits < bestEdits) {
      bestEdits = edits;
      best = a;
    }
  }
  return best;
}

// "unknown key; expected one of: a, b" for a short list; for a long one the closest key and where
// the list is, or its first keys and how many there are: one line, whatever the list.
std::string unknownKeyMessage(std::string_view unknown, const std::vector<std::string>& allowed,
                              std::string_view keysListedIn) {
  const std::string all = joinChoices(allowed);
  if (all.size() <= kListedKeysBytes) return "unknown key; expected one of: " + all;
  std::string message = "unknown key";
  if (const std::string closest = closestKey(unknown, allowed); !closest.empty()) {
    message += "; did you mean \"" + closest + "\"?";
  }
  if (!keysListedIn.empty()) {
    return message + " (the " + std::to_string(allowed.size()) +
           " keys allowed here: " + std::string(keysListedIn) + ")";
  }
  std::string first;
  for (const std::string& a : allowed) {
    if (first.size() + a.size() + 2 > kListedKeysBytes / 2) break;
    first += a + ", ";
  }
  return message + (message.back() == '?' ? " Expected" : "; expected") + " one of: " + first +
         "... (" + std::to_string(allowed.size()) + " keys)";
}

std::string formatNumber(double v) {
  return nlohmann::json(v).dump();
}

}  // namespace

JsonReader::JsonReader(const nlohmann::json& value, std::string file, std::string path)
    : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

std::string JsonReader::childPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

std::string JsonReader::elementPath(std::size_t index) const {
  return path_ + "[" + std::to_string(index) + "]";
}

void JsonReader::fail(const std::string& message) const {
  throw ConfigError(file_, path_, message);
}

void JsonReader::failExpected(const std::string& expected) const {
  fail("expected " + expected + ", got " + describe());
}

std::string JsonReader::describe() const {
  const nlohmann::json& v = *value_;
  switch (v.type()) {
    case nlohmann::json::value_t::null:
      return "null";
    case nlohmann::json::value_t::object:
      return "an object";
    case nlohmann::json::value_t::array:
      return "an array of " + std::to_string(v.size());
    case nlohmann::json::value_t::string: {
      std::string s = v.get<std::string>();
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return "\"" + s + "\"";
    }
    case nlohmann::json::value_t::number_float: {
      const double d = v.get<double>();
      if (std::isnan(d)) return "NaN";
      if (std::isinf(d)) return d > 0 ? "infinity" : "-infinity";
      return v.dump();
    }
    default:
      return v.dump();
  }
}

void JsonReader::expectObject() const {
  if (!value_->is_object()) failExpected("an object");
}

void JsonReader::allowOnly(std::initializer_list<std::string_view> allowed,
                           std::string_view keysListedIn) const {
  std::vector<std::string> v;
  for (std::string_view a : allowed) v.emplace_back(a);
  allowOnly(v, keysListedIn);
}

void JsonReader::allowOnly(const std::vector<std::string>& allowed,
                           std::string_view keysListedIn) const {
  expectObject();
  for (const auto& item : value_->items()) {
    bool known = false;
    for (const std::string& a : allowed) known = known || item.key() == a;
    if (!known) {
      throw ConfigError(file_, childPath(item.key()),
                        unknownKeyMessage(item.key(), allowed, keysListedIn));
    }
  }
}

bool JsonReader::has(std::string_view key) const {
  return value_->is_object() && value_->contains(key);
}

JsonReader JsonReader::at(std::string_view key) const {
  expectObject();
  const auto it = value_->find(key);
  if (it == value_->end()) throw ConfigError(file_, childPath(key), "missing required key");
  return JsonReader(*it, file_, childPath(key));
}

std::optional<JsonReader> JsonReader::find(std::string_view key) const {
  expectObject();
  const auto it = value_->find(key);
  if (it == value_->end()) return std::nullopt;
  return JsonReader(*it, file_, childPath(key));
}

std::vector<std::pair<std::string, JsonReader>> JsonReader::members() const {
  expectObject();
  std::vector<std::pair<std::string, JsonReader>> out;
  for (const auto& item : value_->items()) {
    out.emplace_back(item.key(), JsonReader(item.value(), file_, childPath(item.key())));
  }
  return out;
}

std::vector<JsonReader> JsonReader::elements(std::size_t minCount, std::size_t maxCount) const {
  if (!value_->is_array() || value_->size() < minCount || value_->size() > maxCount) {
    std::string expected = "an array";
    if (minCount == maxCount) {
      expected += " of " + std::to_string(minCount) + " element" + (minCount == 1 ? "" : "s");
    } else if (maxCount == std::numeric_limits<std::size_t>::max()) {
      if (minCount > 0) expected += " of at least " + std::to_string(minCount) + " elements";
    } else {
      expected +=
          " of " + std::to_string(minCount) + " to " + std::to_string(maxCount) + " elements";
    }
    failExpected(expected);
  }
  std::vector<JsonReader> out;
  out.reserve(value_->size());
  for (std::size_t i = 0; i < value_->size(); ++i) {
    out.emplace_back((*value_)[i], file_, elementPath(i));
  }
  return out;
}

double JsonReader::number() const {
  if (!value_->is_number()) failExpected("a number");
  const double d = value_->get<double>();
  if (!std::isfinite(d)) failExpected("a finite number");
  return d;
}

double JsonReader::number(double min, double max) const {
  const double d = number();
  if (d < min || d > max) {
    failExpected("a number in [" + formatNumber(min) + ", " + formatNumber(max) + "]");
  }
  return d;
}

std::int64_t JsonReader::integer(std::int64_t min, std::int64_t max) const {
  const std::string expected =
      "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (value_->is_number_integer() && !value_->is_number_unsigned()) {
    const auto v = value_->get<std::int64_t>();
    if (v < min || v > max) failExpected(expected);
    return v;
  }
  if (value_->is_number_unsigned()) {
    const auto v = value_->get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) ||
        static_cast<std::int64_t>(v) < min || static_cast<std::int64_t>(v) > max) {
      failExpected(expected);
    }
    return static_cast<std::int64_t>(v);
  }
  if (value_->is_number_float()) {
    const double d = value_->get<double>();
    // Bounds compared in double: exact for every range a configuration file uses.
    if (std::isfinite(d) && d == std::floor(d) && d >= static_cast<double>(min) &&
        d <= static_cast<double>(max)) {
      return static_cast<std::int64_t>(d);
    }
  }
  failExpected(expected);
}

bool JsonReader::boolean() const {
  if (!value_->is_boolean()) failExpected("true or false");
  return value_->get<bool>();
}

std::string JsonReader::string() const {
  if (!value_->is_string()) failExpected("a string");
  return value_->get<std::string>();
}

std::string JsonReader::oneOf(std::initializer_list<std::string_view> choices) const {
  std::string expected = "one of";
  bool first = true;
  for (std::string_view c : choices) {
    expected += first ? " \"" : ", \"";
    expected += c;
    expected += '"';
    first = false;
  }
  if (!value_->is_string()) failExpected(expected);
  const std::string s = value_->get<std::string>();
  for (std::string_view c : choices) {
    if (s == c) return s;
  }
  failExpected(expected);
}

std::vector<double> JsonReader::numbers(std::optional<std::size_t> count) const {
  std::vector<double> out;
  const auto items = count ? elements(*count, *count) : elements();
  out.reserve(items.size());
  for (const JsonReader& item : items) out.push_back(item.number());
  return out;
}

double JsonReader::numberOr(std::string_view key, double fallback) const {
  const auto v = find(key);
  return v ? v->number() : fallback;
}

std::int64_t JsonReader::integerOr(std::string_view key, std::int64_t min, std::int64_t max,
                                   std::int64_t fallback) const {
  const auto v = find(key);
  return v ? v->integer(min, max) : fallback;
}

bool JsonReader::booleanOr(std::string_view key, bool fallback) const {
  const auto v = find(key);
  return v ? v->boolean() : fallback;
}

std::string JsonReader::stringOr(std::string_view key, std::string fallback) const {
  const auto v = find(key);
  return v ? v->string() : fallback;
}

}  // namespace volcomp::config
