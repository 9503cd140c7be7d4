#include "volcomp/sim/sim_config.hpp"

#include <cmath>
#include <filesystem>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/json_reader.hpp"

namespace volcomp::sim {
namespace {

using config::JsonReader;

std::string resolve(const std::string& file, const std::string& relative) {
  const std::filesystem::path p(relative);
  if (p.is_absolute()) return relative;
  return (std::filesystem::path(file).parent_path() / p).lexically_normal().string();
}

Vec3 vec3(const JsonReader& r) {
  return r.fixedNumbers<3>();
}

// A number for every axis, or {"X": x, "Y": y, "Z": z} (as the daemon's limiter takes them).
Vec3 perAxis(const JsonReader& r) {
  if (!r.isObject()) {
    const double v = r.number(0.0, 1e6);
    return {v, v, v};
  }
  r.allowOnly({"X", "Y", "Z"});
  return {r.at("X").number(0.0, 1e6), r.at("Y").number(0.0, 1e6), r.at("Z").number(0.0, 1e6)};
}

PathSpec parsePath(const JsonReader& r, const std::string& file) {
  PathSpec p;
  p.type = r.at("type").oneOf({"raster", "circle", "points", "csv"});
  p.feedMmMin = r.at("feed_mm_min").number(1e-3, 1e6);
  if (p.type == "raster") {
    r.allowOnly({"type", "feed_mm_min", "from", "to", "step_mm", "accel_mm_s2"});
    p.from = vec3(r.at("from"));
    p.to = vec3(r.at("to"));
    p.stepMm = r.at("step_mm").number(1e-3, 1e6);
  } else if (p.type == "circle") {
    r.allowOnly({"type", "feed_mm_min", "center", "radius_mm"});
    p.center = vec3(r.at("center"));
    p.radiusMm = r.at("radius_mm").number(1e-3, 1e6);
  } else if (p.type == "points") {
    r.allowOnly({"type", "feed_mm_min", "points", "accel_mm_s2"});
    for (const JsonReader& e : r.at("points").elements(1)) p.points.push_back(vec3(e));
  } else {
    r.allowOnly({"type", "feed_mm_min", "file", "accel_mm_s2"});
    p.csvFile = resolve(file, r.at("file").string());
  }
  if (auto a = r.find("accel_mm_s2")) p.accelMmS2 = a->number(1.0, 1e6);
  return p;
}

}  // namespace

SimConfig parseSimConfig(const nlohmann::json& document, const std::string& file) {
  const JsonReader root(document, file);
  root.allowOnly(
      {"model", "position_semantics", "path", "limits", "heartbeat_timeout_ms",
       "watchdog_ramp_mm_s", "initial_offset_mm", "settle_ms", "tick_ms", "can_broadcast_ms",
       "controller_latency_ms", "position_scan_ms", "transport", "comment"},
      "docs/modbus.md, volcomp-sim");
  SimConfig c;
  c.file = file;
  if (auto m = root.find("model")) c.modelPath = resolve(file, m->string());
  c.machine.semantics = root.at("position_semantics").oneOf({"commanded", "actual"}) == "actual"
                            ? loop::PositionSemantics::Actual
                            : loop::PositionSemantics::Commanded;
  c.path = parsePath(root.at("path"), file);
  if (auto l = root.find("limits")) {
    l->allowOnly({"max_offset_mm", "max_rate_mm_s", "rate_tolerance_ms", "cycle_ms"});
    if (auto v = l->find("cycle_ms")) c.machine.limits.cycleS = v->number(0.0, 1e6) / 1000.0;
    if (auto v = l->find("max_offset_mm")) c.machine.limits.maxOffsetMm = perAxis(*v);
    if (auto v = l->find("max_rate_mm_s")) c.machine.limits.maxRateMmS = perAxis(*v);
    if (auto v = l->find("rate_tolerance_ms")) {
      c.machine.limits.rateToleranceS = v->number(0.0, 1e6) / 1000.0;
    }
  }
  c.machine.heartbeatTimeoutS = root.numberOr("heartbeat_timeout_ms", 0.0) / 1000.0;
  if (c.machine.heartbeatTimeoutS < 0.0) root.at("heartbeat_timeout_ms").failExpected(">= 0");
  c.machine.watchdogRampMmS = root.numberOr("watchdog_ramp_mm_s", 1.0);
  if (!(c.machine.watchdogRampMmS > 0.0)) root.at("watchdog_ramp_mm_s").failExpected("> 0");
  if (auto v = root.find("initial_offset_mm")) c.machine.initialOffsetMm = vec3(*v);
  c.machine.settleS = root.numberOr("settle_ms", 0.0) / 1000.0;
  if (c.machine.settleS < 0.0) root.at("settle_ms").failExpected(">= 0");
  if (auto v = root.find("tick_ms")) c.tickS = v->number(0.1, 1000.0) / 1000.0;
  if (auto v = root.find("controller_latency_ms")) {
    c.machine.axisLatencyS = v->number(0.0, 100.0) / 1000.0;
  }
  if (auto v = root.find("position_scan_ms"))
    c.machine.positionScanS = v->number(0.0, 100.0) / 1000.0;
  c.transport = config::parseTransportSettings(root.at("transport").json(), file, "transport");
  if (const auto* layout = std::get_if<can::CanLayout>(&c.transport)) {
    if (auto v = root.find("can_broadcast_ms")) c.canBroadcastS = v->number(0.1, 1000.0) / 1000.0;
    c.machine.limits.quantumMm = offsetQuantumMm(*layout);
  } else {
    if (root.find("can_broadcast_ms")) {
      throw config::ConfigError(file, "can_broadcast_ms", "applies to a CAN transport only");
    }
    const auto& registers = std::get<modbus::ModbusSettings>(c.transport).registers;
    c.machine.limits.quantumMm = offsetQuantumMm(registers);
    if (registers.timestamp) c.machine.timestampTickS = registers.timestamp->tickUs * 1e-6;
  }
  return c;
}

SimConfig loadSimConfig(const std::string& file) {
  return parseSimConfig(config::readJsonFile(file), file);
}

Path makePath(const PathSpec& s) {
  if (s.type == "circle") return Path::circle(s.center, s.radiusMm, s.feedMmMin);
  Path p = s.type == "raster"   ? Path::raster(s.from, s.to, s.stepMm, s.feedMmMin)
           : s.type == "points" ? Path::polyline(s.points, s.feedMmMin)
                                : Path::fromCsv(s.csvFile, s.feedMmMin);
  return s.accelMmS2 > 0.0 ? p.withAcceleration(s.accelMmS2) : p;
}

Vec3 offsetQuantumMm(const modbus::RegisterMap& map) noexcept {
  Vec3 q{};
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& f = map.offset[k].format;
    const bool isFloat =
        f.type == modbus::RegisterType::Float32 || f.type == modbus::RegisterType::Float64;
    q[k] = isFloat ? 0.0 : 1.0 / f.countsPerMm;
  }
  return q;
}

Vec3 offsetQuantumMm(const can::CanLayout& layout) noexcept {
  Vec3 q{};
  for (const can::FrameLayout& frame : layout.outputFrames) {
    for (const can::FieldSignal& s : frame.signals) {
      const auto k =
          static_cast<std::size_t>(s.field) - static_cast<std::size_t>(can::Field::OffsetX);
      if (k >= 3) continue;
      const bool isFloat = s.spec.valueType == can::ValueType::Float32 ||
                           s.spec.valueType == can::ValueType::Float64;
      q[k] = isFloat ? 0.0 : std::abs(s.spec.scale);
    }
  }
  return q;
}

}  // namespace volcomp::sim
