#include "cli_support.hpp"

#include <charconv>
#include <cmath>

#include "volcomp/format/numbers.hpp"

namespace volcomp::cli {

std::string_view trim(std::string_view text) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && isSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && isSpace(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> splitFields(std::string_view text) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(text.substr(start)));
      return fields;
    }
    fields.push_back(trim(text.substr(start, comma - start)));
    start = comma + 1;
  }
}

bool parseDouble(std::string_view field, double& value) {
  // from_chars rejects a leading '+', which people type; skip it.
  if (field.size() > 1 && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  return ec == std::errc() && end == field.data() + field.size() && std::isfinite(value);
}

std::vector<double> parseNumberList(std::string_view text, std::string_view option,
                                    std::size_t count) {
  const std::vector<std::string_view> fields = splitFields(text);
  const std::string expected = count > 0 ? std::to_string(count) + " comma-separated numbers"
                                         : std::string("comma-separated numbers");
  const auto bad = [&](const std::string& why) {
    return UsageError(std::string(option) + ": expected " + expected + ", got \"" +
                      std::string(text) + "\" (" + why + ")");
  };
  std::vector<double> values;
  for (std::string_view field : fields) {
    double value = 0.0;
    if (!parseDouble(field, value)) {
      throw bad("\"" + std::string(field) + "\" is not a finite number");
    }
    values.push_back(value);
  }
  if (count > 0 && values.size() != count) throw bad(std::to_string(values.size()) + " given");
  return values;
}

model::Directions parseDirections(std::string_view text) {
  const std::vector<std::string_view> fields = splitFields(text);
  const UsageError bad(
      "--direction: expected three of +, - or 0 (unknown) such as \"+,-,+\", got \"" +
      std::string(text) + "\"");
  if (fields.size() != 3) throw bad;
  model::Directions directions{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (fields[axis] == "+") {
      directions[axis] = model::Direction::Positive;
    } else if (fields[axis] == "-") {
      directions[axis] = model::Direction::Negative;
    } else if (fields[axis] == "0" || fields[axis] == "?") {
      directions[axis] = model::Direction::Unknown;
    } else {
      throw bad;
    }
  }
  return directions;
}

void appendDouble(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

std::string formatDouble(double value) {
  std::string out;
  appendDouble(out, value);
  return out;
}

std::string fixedMicrometres(double mm) {
  return format::fixed(mm * 1000.0, 3);
}

std::string axisList(std::uint8_t mask) {
  std::string out;
  for (int axis = 0; axis < 3; ++axis) {
    if ((mask & (1u << axis)) == 0) continue;
    if (!out.empty()) out += ", ";
    out += "XYZ"[axis];
  }
  return out;
}

}  // namespace volcomp::cli
