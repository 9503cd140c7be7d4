#include "can_section.hpp"

#include <charconv>
#include <filesystem>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {
namespace {

constexpr std::int64_t kExtendedIdMax = 0x1FFFFFFF;
constexpr std::int64_t kStandardIdMax = 0x7FF;

/// A CAN identifier: an integer, or a string in hexadecimal ("0x100") or decimal.
std::uint32_t readId(const JsonReader& r, bool extended) {
  const std::int64_t max = extended ? kExtendedIdMax : kStandardIdMax;
  const std::string expected = std::string("a ") + (extended ? "29" : "11") +
                               "-bit identifier (integer or \"0x...\" string, at most " +
                               (extended ? "0x1FFFFFFF" : "0x7FF") + ")";
  if (r.isNumber()) {
    if (!r.json().is_number_integer() && !r.json().is_number_unsigned()) r.failExpected(expected);
    const auto v = r.json().get<std::int64_t>();
    if (v < 0 || v > max) r.failExpected(expected);
    return static_cast<std::uint32_t>(v);
  }
  if (!r.isString()) r.failExpected(expected);
  const std::string text = r.string();
  std::string_view digits = text;
  int base = 10;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) {
    digits.remove_prefix(2);
    base = 16;
  }
  std::uint64_t v = 0;
  auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, base);
  if (ec != std::errc{} || ptr != digits.data() + digits.size() ||
      v > static_cast<std::uint64_t>(max))
    r.failExpected(expected);
  return static_cast<std::uint32_t>(v);
}

CanSignalRef readSignal(const JsonReader& r) {
  r.expectObject();
  CanSignalRef ref;
  ref.keyPath = r.path();
  if (r.has("dbc")) {
    r.allowOnly({"dbc"});
    ref.dbcName = r.at("dbc").string();
    if (ref.dbcName.empty()) r.at("dbc").fail("expected a DBC signal name, got an empty string");
    return ref;
  }
  r.allowOnly({"id", "extended", "start_bit", "length", "byte_order", "type", "scale", "offset",
               "min", "max", "unit"});
  can::SignalSpec& s = ref.spec;
  s.name = ref.keyPath;
  s.extended = r.booleanOr("extended", false);
  s.frameId = readId(r.at("id"), s.extended);
  s.startBit = static_cast<unsigned>(r.at("start_bit").integer(0, 511));
  s.length = static_cast<unsigned>(r.at("length").integer(1, 64));
  if (auto order = r.find("byte_order"))
    s.byteOrder = order->oneOf({"intel", "motorola"}) == "intel" ? can::ByteOrder::Intel
                                                                 : can::ByteOrder::Motorola;
  if (auto type = r.find("type")) {
    const std::string t = type->oneOf({"unsigned", "signed", "float32", "float64"});
    s.valueType = t == "unsigned"  ? can::ValueType::Unsigned
                  : t == "signed"  ? can::ValueType::Signed
                  : t == "float32" ? can::ValueType::Float32
                                   : can::ValueType::Float64;
  }
  s.scale = r.numberOr("scale", 1.0);
  if (s.scale == 0.0) r.at("scale").fail("expected a non-zero scale, got 0");
  s.offset = r.numberOr("offset", 0.0);
  s.minimum = r.numberOr("min", 0.0);
  s.maximum = r.numberOr("max", 0.0);
  if (s.minimum > s.maximum) r.fail("min must not exceed max");
  s.unit = r.stringOr("unit", "");
  return ref;
}

std::array<CanSignalRef, 3> readAxes(const JsonReader& r) {
  r.allowOnly({"X", "Y", "Z"});
  return {readSignal(r.at("X")), readSignal(r.at("Y")), readSignal(r.at("Z"))};
}

CanSyncFrame readSync(const JsonReader& r, bool fd) {
  r.allowOnly({"id", "extended", "data"});
  CanSyncFrame sync;
  sync.extended = r.booleanOr("extended", false);
  sync.id = readId(r.at("id"), sync.extended);
  if (auto data = r.find("data")) {
    const std::size_t maxCount = fd ? 64 : 8;
    for (const JsonReader& byte : data->elements(0, maxCount))
      sync.data.push_back(static_cast<std::uint8_t>(byte.integer(0, 255)));
    const std::size_t n = sync.data.size();
    const bool validFd =
        n <= 8 || n == 12 || n == 16 || n == 20 || n == 24 || n == 32 || n == 48 || n == 64;
    if (!validFd) data->fail("a CAN FD payload must be 0..8, 12, 16, 20, 24, 32, 48 or 64 bytes");
  }
  return sync;
}

}  // namespace

CanSection parseCanSection(const nlohmann::json& section, const std::string& file,
                           const std::string& keyPath) {
  const JsonReader root(section, file, keyPath);
  root.allowOnly({"type", "interface", "fd", "bitrate_switch", "trigger", "dbc", "timeouts", "sync",
                  "inputs", "outputs"});
  CanSection c;
  c.file = file;
  c.keyPath = keyPath;
  if (auto type = root.find("type")) type->oneOf({"can"});
  c.interfaceName = root.at("interface").string();
  // IFNAMSIZ is 16 including the terminating zero.
  if (c.interfaceName.empty() || c.interfaceName.size() > 15)
    root.at("interface").failExpected("an interface name of 1 to 15 characters");
  c.fd = root.booleanOr("fd", false);
  c.bitrateSwitch = root.booleanOr("bitrate_switch", true);
  c.trigger = root.at("trigger").oneOf({"broadcast", "sync"}) == "broadcast"
                  ? can::Trigger::Broadcast
                  : can::Trigger::Sync;
  if (auto dbc = root.find("dbc")) {
    const std::filesystem::path dbcFile = dbc->string();
    c.dbcPath = dbcFile.is_absolute()
                    ? dbcFile.string()
                    : (std::filesystem::path(file).parent_path() / dbcFile).string();
  }
  if (auto timeouts = root.find("timeouts")) {
    timeouts->allowOnly({"stale_ms", "response_ms"});
    if (auto stale = timeouts->find("stale_ms")) c.staleTimeoutMs = stale->number(0.1, 60000.0);
    if (auto response = timeouts->find("response_ms"))
      c.responseTimeoutMs = response->number(0.1, 60000.0);
  }
  if (c.trigger == can::Trigger::Sync)
    c.sync = readSync(root.at("sync"), c.fd);
  else if (root.has("sync"))
    root.at("sync").fail("a SYNC frame is only used with \"trigger\": \"sync\"");

  const JsonReader inputs = root.at("inputs");
  inputs.allowOnly({"position", "enable", "homed", "sequence", "applied_offset"});
  c.position = readAxes(inputs.at("position"));
  c.enable = readSignal(inputs.at("enable"));
  c.homed = readSignal(inputs.at("homed"));
  if (auto sequence = inputs.find("sequence")) {
    if (sequence->isArray()) {
      for (const JsonReader& s : sequence->elements(1)) c.sequence.push_back(readSignal(s));
    } else {
      c.sequence.push_back(readSignal(*sequence));
    }
  }
  if (auto applied = inputs.find("applied_offset")) c.appliedOffset = readAxes(*applied);

  const JsonReader outputs = root.at("outputs");
  outputs.allowOnly({"offset", "status", "heartbeat"});
  c.offset = readAxes(outputs.at("offset"));
  c.status = readSignal(outputs.at("status"));
  c.heartbeat = readSignal(outputs.at("heartbeat"));
  return c;
}

}  // namespace volcomp::config
