#pragma once
// Defensive reading of one JSON object of an input document: absent or null fields are
// std::nullopt, a field of the wrong type is skipped with a note naming file and key path, and
// the fields not asked for can be listed afterwards (for the generic "further figures" tables).

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/report/inputs.hpp"

namespace volcomp::report::detail {

class Fields {
 public:
  /// `object` must outlive this. A non-object gives no fields (and a note).
  Fields(const nlohmann::json& object, std::string file, std::string path, Notes& notes);

  std::optional<double> number(const std::string& key);
  std::optional<std::int64_t> integer(const std::string& key);
  std::optional<bool> boolean(const std::string& key);
  /// "" when absent.
  std::string text(const std::string& key);
  /// nullptr when absent or not an object/array (the latter with a note).
  const nlohmann::json* object(const std::string& key);
  const nlohmann::json* array(const std::string& key);
  /// An array of numbers; empty when absent, a note when an element is not a number.
  std::vector<double> numbers(const std::string& key);

  /// Marks a field as shown elsewhere, so that unread() leaves it out.
  void skip(const std::string& key) { read_.insert(key); }

  /// Key path of a field, for notes and nested readers ("residuals.before").
  std::string path(const std::string& key) const;
  const std::string& file() const noexcept { return file_; }
  Notes& notes() noexcept { return notes_; }

  /// Scalars (and scalars one object deep, as "key.sub") not read through this reader, with
  /// numbers shown to 6 significant digits.
  std::vector<Figure> unread() const;

 private:
  const nlohmann::json* find(const std::string& key);
  void wrongType(const std::string& key, const char* expected);

  const nlohmann::json& object_;
  std::string file_;
  std::string path_;
  Notes& notes_;
  std::set<std::string> read_;
};

/// Checks the document's "format" against `family` + "/N" and notes a version newer than 1;
/// throws config::ConfigError naming `expected` (what the document should be) otherwise.
void checkFormat(Fields& top, const std::string& family, const std::string& expected);

}  // namespace volcomp::report::detail
