#pragma once
/// Key-path JSON reading for every configuration file of the project (model files, daemon,
/// Modbus and CAN configuration). Each failure throws ConfigError(file, key path, what was
/// expected), so messages read like
///   "daemon.json: modbus.port: expected an integer in [1, 65535], got 70000".
///
/// Use:
///   nlohmann::json doc = volcomp::config::readJsonFile(path);  // missing file, bad syntax (with
///                                                              // line/column), duplicate keys,
///                                                              // number overflow -> ConfigError
///   volcomp::config::JsonReader root(doc, path);               // a view at key path ""
///   root.allowOnly({"name", "period_ms", "modbus"});           // unknown key -> ConfigError
///   std::string name = root.at("name").string();               // required key
///   double periodMs = root.numberOr("period_ms", 1.0);         // optional key with default
///   JsonReader modbus = root.at("modbus");                     // path "modbus"
///   auto port = modbus.at("port").integer(1, 65535);           // path "modbus.port"
///   for (const JsonReader& link : root.at("links").elements()) // paths "links[0]", "links[1]"...
///     ...
///   if (auto extra = root.find("extra")) extra->expectObject();
///
/// A JsonReader is a cheap view: it points into the document, which must outlive it. Numbers are
/// always checked finite (NaN or infinity never get through, whatever built the document).

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"

namespace volcomp::config {

/// Reads and parses a JSON file. Throws ConfigError naming the file when it cannot be read, when
/// the text is not JSON (message with line and column), when an object repeats a key (key path of
/// the object) or when a number overflows a double (line and column).
nlohmann::json readJsonFile(const std::string& path);

/// Same for text already in memory; `file` is used in messages only.
nlohmann::json parseJsonText(std::string_view text, const std::string& file);

/// Longest list of allowed keys (bytes, ", " between keys) an unknown-key message writes out.
inline constexpr std::size_t kListedKeysBytes = 160;

class JsonReader {
 public:
  /// A view of `value` at `path` ("" for the document root) of `file` (used in messages).
  JsonReader(const nlohmann::json& value, std::string file, std::string path = {});

  const nlohmann::json& json() const noexcept { return *value_; }
  const std::string& file() const noexcept { return file_; }
  /// Key path of this value, e.g. "components.EXX.values[3]" ("" at the root).
  const std::string& path() const noexcept { return path_; }
  /// Key path of a member / element of this value.
  std::string childPath(std::string_view key) const;
  std::string elementPath(std::size_t index) const;

  /// Throws ConfigError(file, path, message).
  [[noreturn]] void fail(const std::string& message) const;
  /// Throws ConfigError(file, path, "expected " + expected + ", got " + describe()).
  [[noreturn]] void failExpected(const std::string& expected) const;
  /// Short description of the value for messages: `"abc"`, `12.5`, `an object`, `null`...
  std::string describe() const;

  bool isObject() const noexcept { return value_->is_object(); }
  bool isArray() const noexcept { return value_->is_array(); }
  bool isNumber() const noexcept { return value_->is_number(); }
  bool isString() const noexcept { return value_->is_string(); }

  // Objects ------------------------------------------------------------------------------------
  void expectObject() const;
  /// Expects an object whose keys are all in `allowed`; otherwise fails at the first unknown
  /// key's path with "unknown key; expected one of: a, b, c". A list longer than kListedKeysBytes
  /// is not written out, so that the message stays one short line: the message names the allowed
  /// key closest to the unknown one (when one is within a few edits) and where the keys are
  /// listed, `keysListedIn` (e.g. "docs/daemon.md, Configuration reference"); without it, the
  /// first keys and how many there are.
  void allowOnly(std::initializer_list<std::string_view> allowed,
                 std::string_view keysListedIn = {}) const;
  void allowOnly(const std::vector<std::string>& allowed, std::string_view keysListedIn = {}) const;
  bool has(std::string_view key) const;
  /// Required member; fails at the member's path with "missing required key" when absent.
  JsonReader at(std::string_view key) const;
  /// Optional member.
  std::optional<JsonReader> find(std::string_view key) const;
  /// Members of an object in key order.
  std::vector<std::pair<std::string, JsonReader>> members() const;

  // Arrays -------------------------------------------------------------------------------------
  /// Elements of an array with between minCount and maxCount elements.
  std::vector<JsonReader> elements(
      std::size_t minCount = 0,
      std::size_t maxCount = std::numeric_limits<std::size_t>::max()) const;
  /// Number of elements (array) or members (object); 0 for anything else.
  std::size_t size() const noexcept { return value_->size(); }

  // Scalars ------------------------------------------------------------------------------------
  /// A finite number.
  double number() const;
  /// A finite number in [min, max].
  double number(double min, double max) const;
  /// An integral number in [min, max] (1e3 is accepted, 1.5 is not).
  std::int64_t integer(std::int64_t min, std::int64_t max) const;
  bool boolean() const;
  std::string string() const;
  /// A string equal to one of `choices`.
  std::string oneOf(std::initializer_list<std::string_view> choices) const;
  /// An array of finite numbers; with `count` given, exactly that many.
  std::vector<double> numbers(std::optional<std::size_t> count = std::nullopt) const;
  template <std::size_t N>
  std::array<double, N> fixedNumbers() const {
    const std::vector<double> v = numbers(N);
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = v[i];
    return out;
  }

  // Optional members with defaults ---------------------------------------------------------------
  double numberOr(std::string_view key, double fallback) const;
  std::int64_t integerOr(std::string_view key, std::int64_t min, std::int64_t max,
                         std::int64_t fallback) const;
  bool booleanOr(std::string_view key, bool fallback) const;
  std::string stringOr(std::string_view key, std::string fallback) const;

 private:
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

}  // namespace volcomp::config
