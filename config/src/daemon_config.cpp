#include "volcomp/config/daemon_config.hpp"

#include <cstdio>
#include <filesystem>
#include <optional>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {
namespace {

std::string shortNumber(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", v);
  return buffer;
}

// A strictly positive number no larger than `max` (JsonReader::number takes closed ranges).
double positiveNumber(const JsonReader& value, double max) {
  const double v = value.number();
  if (!(v > 0.0) || v > max) value.failExpected("a number in (0, " + shortNumber(max) + "]");
  return v;
}

std::string resolveAgainst(const std::string& file, const std::string& relative) {
  const std::filesystem::path p(relative);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (std::filesystem::path(file).parent_path() / p).lexically_normal().string();
}

}  // namespace

DaemonConfig parseDaemonConfig(const nlohmann::json& document, const std::string& file) {
  const JsonReader root(document, file);
  root.allowOnly({"cycle_period_ms", "position_semantics", "limiter", "stale_timeout_ms",
                  "frozen_positions_are_stale", "travel_margin_mm", "direction_hysteresis_mm",
                  "offset_readback", "plc_zero_after_ms", "model", "reconnect", "log_level",
                  "transport"});
  DaemonConfig c;
  c.file = file;
  if (auto v = root.find("cycle_period_ms")) c.cyclePeriodMs = v->number(1.0, 1000.0);
  c.positionSemantics = root.at("position_semantics").oneOf({"commanded", "actual"}) == "actual"
                            ? loop::PositionSemantics::Actual
                            : loop::PositionSemantics::Commanded;

  const JsonReader limiter = root.at("limiter");
  limiter.allowOnly({"max_offset_mm", "max_rate_mm_s", "max_accel_mm_s2"});
  c.limiter.maxOffsetMm = positiveNumber(limiter.at("max_offset_mm"), 100.0);
  c.limiter.maxRateMmS = positiveNumber(limiter.at("max_rate_mm_s"), 1000.0);
  if (auto v = limiter.find("max_accel_mm_s2")) c.limiter.maxAccelMmS2 = v->number(0.0, 1e6);

  if (auto v = root.find("stale_timeout_ms")) {
    c.staleTimeoutMs = v->number(0.0, 60000.0);
    if (!(c.staleTimeoutMs > c.cyclePeriodMs)) {
      v->failExpected("a timeout longer than cycle_period_ms (" + shortNumber(c.cyclePeriodMs) +
                      " ms)");
    }
  } else if (!(c.staleTimeoutMs > c.cyclePeriodMs)) {
    root.fail(
        "the default stale_timeout_ms (500 ms) is not longer than cycle_period_ms; set "
        "stale_timeout_ms");
  }
  c.frozenPositionsAreStale = root.booleanOr("frozen_positions_are_stale", false);
  if (auto v = root.find("travel_margin_mm")) c.travelMarginMm = v->number(0.0, 1000.0);
  if (auto v = root.find("direction_hysteresis_mm")) c.directionHysteresisMm = v->number(0.0, 10.0);

  c.offsetReadback = root.booleanOr("offset_readback", true);
  if (auto v = root.find("plc_zero_after_ms")) c.plcZeroAfterMs = positiveNumber(*v, 600000.0);
  if (!c.offsetReadback && !c.plcZeroAfterMs) {
    root.at("plc_zero_after_ms");  // throws "missing required key" at that path
  }

  const JsonReader model = root.at("model");
  const std::string modelName = model.string();
  if (modelName.empty()) model.failExpected("a model file name");
  c.modelPath = resolveAgainst(file, modelName);

  if (auto reconnect = root.find("reconnect")) {
    reconnect->allowOnly({"initial_ms", "max_ms"});
    if (auto v = reconnect->find("initial_ms")) c.reconnect.initialMs = positiveNumber(*v, 60000.0);
    if (auto v = reconnect->find("max_ms")) {
      c.reconnect.maxMs = positiveNumber(*v, 600000.0);
      if (c.reconnect.maxMs < c.reconnect.initialMs) {
        v->failExpected("a delay not shorter than reconnect.initial_ms");
      }
    } else if (c.reconnect.maxMs < c.reconnect.initialMs) {
      c.reconnect.maxMs = c.reconnect.initialMs;
    }
  }
  if (auto v = root.find("log_level")) {
    c.logLevel = v->oneOf({"trace", "debug", "info", "warn", "error", "critical", "off"});
  }

  c.transport = parseTransportSettings(root.at("transport").json(), file, "transport");
  return c;
}

DaemonConfig loadDaemonConfig(const std::string& path) {
  return parseDaemonConfig(readJsonFile(path), path);
}

}  // namespace volcomp::config
