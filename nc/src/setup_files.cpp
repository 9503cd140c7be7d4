#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "volcomp/config/json_reader.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/numbers.hpp"
#include "volcomp/nc/setup.hpp"

namespace volcomp::nc {
namespace {

constexpr std::array<const char*, kCoordinateSystems> kNames{"G54", "G55",   "G56",   "G57",  "G58",
                                                             "G59", "G59.1", "G59.2", "G59.3"};

// Calls fn(lineNumber, line) for every line of `text` (without its line ending).
template <typename Fn>
void forEachLine(std::string_view text, Fn&& fn) {
  long number = 0;
  while (!text.empty()) {
    const std::size_t nl = text.find('\n');
    std::string_view line = text.substr(0, nl);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    fn(++number, line);
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
}

std::size_t skipBlanks(std::string_view line, std::size_t i) {
  while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  return i;
}

}  // namespace

double mmPerUnit(LengthUnit unit) noexcept {
  return unit == LengthUnit::Inch ? 25.4 : 1.0;
}

const char* coordinateSystemName(int index) noexcept {
  return index >= 0 && index < kCoordinateSystems ? kNames[static_cast<std::size_t>(index)] : "?";
}

int coordinateSystemIndex(std::string_view name) noexcept {
  for (int i = 0; i < kCoordinateSystems; ++i) {
    const std::string_view candidate = kNames[static_cast<std::size_t>(i)];
    if (candidate.size() == name.size() &&
        std::equal(candidate.begin(), candidate.end(), name.begin(), [](char a, char b) {
          return a == std::toupper(static_cast<unsigned char>(b));
        })) {
      return i;
    }
  }
  return -1;
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw NcError(path, 0, 0, "cannot open the file");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw NcError(path, 0, 0, "cannot read the file");
  return text;
}

void parseVarText(std::string_view text, const std::string& file, LengthUnit machineUnits,
                  WorkOffsets& offsets) {
  const double unit = mmPerUnit(machineUnits);
  bool g92Enabled = false;
  Eigen::Vector3d g92 = Eigen::Vector3d::Zero();
  forEachLine(text, [&](long lineNo, std::string_view line) {
    std::size_t i = skipBlanks(line, 0);
    if (i == line.size()) return;
    double number = 0.0;
    double value = 0.0;
    std::size_t pos = i;
    if (!scanNumber(line, pos, number, false) || number != std::floor(number) || number < 1) {
      throw NcError(file, lineNo, static_cast<int>(i) + 1,
                    "expected a parameter number and a value (\"5221 10.0\")");
    }
    const std::size_t valueAt = skipBlanks(line, pos);
    pos = valueAt;
    if (!scanNumber(line, pos, value, false) || skipBlanks(line, pos) != line.size()) {
      throw NcError(file, lineNo, static_cast<int>(valueAt) + 1,
                    "expected a number after parameter " + std::to_string(std::lround(number)));
    }
    const long p = std::lround(number);
    if (p == 5210) g92Enabled = value != 0.0;
    if (p >= 5211 && p <= 5213) g92[p - 5211] = value * unit;
    if (p == 5220) {
      if (value < 1 || value > kCoordinateSystems || value != std::floor(value)) {
        throw NcError(file, lineNo, static_cast<int>(valueAt) + 1,
                      "parameter 5220 (active coordinate system) must be 1 .. 9");
      }
      offsets.active = static_cast<int>(value) - 1;
    }
    if (p >= 5221 && p < 5221 + 20 * kCoordinateSystems) {
      const long k = (p - 5221) / 20;
      const long slot = (p - 5221) % 20;
      if (slot <= 2) offsets.systemsMm[static_cast<std::size_t>(k)][slot] = value * unit;
      if (slot == 9) offsets.rotationDeg[static_cast<std::size_t>(k)] = value;
    }
  });
  offsets.g92Mm = g92Enabled ? g92 : Eigen::Vector3d::Zero();
}

void parseToolTableText(std::string_view text, const std::string& file, LengthUnit machineUnits,
                        ToolTable& tools) {
  const double unit = mmPerUnit(machineUnits);
  forEachLine(text, [&](long lineNo, std::string_view line) {
    const std::size_t semicolon = line.find(';');
    if (semicolon != std::string_view::npos) line = line.substr(0, semicolon);
    std::size_t i = skipBlanks(line, 0);
    if (i == line.size()) return;
    std::optional<int> toolNumber;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    while (i < line.size()) {
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(line[i])));
      std::size_t pos = i + 1;
      double value = 0.0;
      if (letter < 'A' || letter > 'Z' || !scanNumber(line, pos, value, false)) {
        throw NcError(file, lineNo, static_cast<int>(i) + 1,
                      "expected a tool table field such as T1, P1, Z25.4 or D6");
      }
      if (letter == 'T') {
        if (!isToolNumber(value)) {
          throw NcError(file, lineNo, static_cast<int>(i) + 1,
                        "tool number must be a whole number in 0..2147483647");
        }
        toolNumber = static_cast<int>(value);
      } else if (letter >= 'X' && letter <= 'Z') {
        offset[letter - 'X'] = value * unit;
      }
      i = skipBlanks(line, pos);
    }
    if (!toolNumber) throw NcError(file, lineNo, 1, "tool table line without a T field");
    tools[*toolNumber] = offset;
  });
}

void parseWorkOffsetsJson(std::string_view text, const std::string& file, WorkOffsets& offsets,
                          ToolTable& tools) {
  const nlohmann::json doc = config::parseJsonText(text, file);
  const config::JsonReader root(doc, file);
  root.allowOnly({"format", "units", "active", "coordinate_systems", "g92", "tools"});
  if (auto format = root.find("format")) format->oneOf({"volcomp-work-offsets/1"});
  const double unit = root.stringOr("units", "mm") == "inch" ? 25.4 : 1.0;
  if (auto units = root.find("units")) units->oneOf({"mm", "inch"});
  const auto vector = [&](const config::JsonReader& r) {
    const auto v = r.fixedNumbers<3>();
    return Eigen::Vector3d(v[0] * unit, v[1] * unit, v[2] * unit);
  };
  if (auto systems = root.find("coordinate_systems")) {
    systems->expectObject();
    for (const auto& [name, value] : systems->members()) {
      const int index = coordinateSystemIndex(name);
      if (index < 0) {
        config::JsonReader(value.json(), file, value.path())
            .fail("unknown coordinate system; expected G54 .. G59, G59.1, G59.2 or G59.3");
      }
      offsets.systemsMm[static_cast<std::size_t>(index)] = vector(value);
    }
  }
  if (auto active = root.find("active")) {
    const int index = coordinateSystemIndex(active->string());
    if (index < 0) active->failExpected("one of G54 .. G59, G59.1, G59.2, G59.3");
    offsets.active = index;
  }
  if (auto g92 = root.find("g92")) offsets.g92Mm = vector(*g92);
  if (auto table = root.find("tools")) {
    table->expectObject();
    for (const auto& [name, value] : table->members()) {
      int number = -1;
      const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), number);
      if (ec != std::errc() || end != name.data() + name.size() || number < 0) {
        value.fail("tool numbers are whole numbers >= 0 (\"1\", \"12\")");
      }
      if (value.isNumber()) {
        tools[number] = Eigen::Vector3d(0.0, 0.0, value.number() * unit);
      } else {
        tools[number] = vector(value);
      }
    }
  }
}

void readWorkOffsetsFile(const std::string& path, LengthUnit machineUnits, WorkOffsets& offsets,
                         ToolTable& tools) {
  const auto endsWith = [&](std::string_view suffix) {
    return path.size() >= suffix.size() &&
           std::equal(suffix.rbegin(), suffix.rend(), path.rbegin(), [](char a, char b) {
             return a == std::tolower(static_cast<unsigned char>(b));
           });
  };
  if (endsWith(".var")) {
    parseVarText(readTextFile(path), path, machineUnits, offsets);
  } else if (endsWith(".json")) {
    parseWorkOffsetsJson(readTextFile(path), path, offsets, tools);
  } else {
    throw NcError(path, 0, 0,
                  "work offsets: expected a LinuxCNC parameter file (.var) or a JSON file (.json)");
  }
}

void readToolTableFile(const std::string& path, LengthUnit machineUnits, ToolTable& tools) {
  parseToolTableText(readTextFile(path), path, machineUnits, tools);
}

}  // namespace volcomp::nc
