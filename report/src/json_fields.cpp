#include "json_fields.hpp"

#include <cmath>

#include "volcomp/config/config_error.hpp"
#include "volcomp/format/numbers.hpp"

namespace volcomp::report::detail {

using nlohmann::json;

Fields::Fields(const json& object, std::string file, std::string path, Notes& notes)
    : object_(object), file_(std::move(file)), path_(std::move(path)), notes_(notes) {
  if (!object_.is_object()) {
    notes_.push_back(file_ + ": " + (path_.empty() ? std::string("the document") : path_) +
                     " is not a JSON object; not shown");
  }
}

std::string Fields::path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

const json* Fields::find(const std::string& key) {
  read_.insert(key);
  if (!object_.is_object()) return nullptr;
  const auto it = object_.find(key);
  if (it == object_.end() || it->is_null()) return nullptr;
  return &*it;
}

void Fields::wrongType(const std::string& key, const char* expected) {
  notes_.push_back(file_ + ": " + path(key) + ": expected " + expected + "; not shown");
}

std::optional<double> Fields::number(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_number()) {
    wrongType(key, "a number");
    return std::nullopt;
  }
  const double number = value->get<double>();
  if (!std::isfinite(number)) return std::nullopt;
  return number;
}

std::optional<std::int64_t> Fields::integer(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return std::nullopt;
  if (value->is_number_integer()) return value->get<std::int64_t>();
  if (value->is_number_float()) {
    const double number = value->get<double>();
    if (std::isfinite(number) && number == std::floor(number)) {
      return static_cast<std::int64_t>(number);
    }
  }
  wrongType(key, "an integer");
  return std::nullopt;
}

std::optional<bool> Fields::boolean(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return std::nullopt;
  if (!value->is_boolean()) {
    wrongType(key, "true or false");
    return std::nullopt;
  }
  return value->get<bool>();
}

std::string Fields::text(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return {};
  if (value->is_string()) return value->get<std::string>();
  if (value->is_number() || value->is_boolean()) return value->dump();
  wrongType(key, "a string");
  return {};
}

const json* Fields::object(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return nullptr;
  if (!value->is_object()) {
    wrongType(key, "an object");
    return nullptr;
  }
  return value;
}

const json* Fields::array(const std::string& key) {
  const json* value = find(key);
  if (value == nullptr) return nullptr;
  if (!value->is_array()) {
    wrongType(key, "an array");
    return nullptr;
  }
  return value;
}

std::vector<double> Fields::numbers(const std::string& key) {
  std::vector<double> out;
  const json* values = array(key);
  if (values == nullptr) return out;
  for (std::size_t i = 0; i < values->size(); ++i) {
    const json& v = (*values)[i];
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      notes_.push_back(file_ + ": " + path(key) + "[" + std::to_string(i) +
                       "]: expected a number; the list is not shown");
      return {};
    }
    out.push_back(v.get<double>());
  }
  return out;
}

namespace {

std::string scalarText(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number()) return format::general(value.get<double>());
  return value.dump();
}

}  // namespace

std::vector<Figure> Fields::unread() const {
  std::vector<Figure> out;
  if (!object_.is_object()) return out;
  for (const auto& [key, value] : object_.items()) {
    if (read_.count(key) != 0 || value.is_null()) continue;
    if (value.is_primitive()) {
      out.push_back({key, scalarText(value)});
    } else if (value.is_object()) {
      for (const auto& [sub, inner] : value.items()) {
        if (inner.is_primitive() && !inner.is_null()) {
          out.push_back({key + "." + sub, scalarText(inner)});
        }
      }
    }
  }
  return out;
}

void checkFormat(Fields& top, const std::string& family, const std::string& expected) {
  const std::string format = top.text("format");
  if (format.rfind(family + "/", 0) != 0) {
    throw config::ConfigError(top.file(), "format",
                              "expected " + expected + ", got \"" + format + "\"");
  }
  if (format != family + "/1") {
    top.notes().push_back(top.file() + ": format " + format +
                          " is newer than this volcomp knows; the fields it knows are shown");
  }
}

}  // namespace volcomp::report::detail
