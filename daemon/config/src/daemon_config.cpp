#include "volcomp/config/daemon_config.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <optional>

#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/transport_limits.hpp"
#include "volcomp/format/numbers.hpp"

namespace volcomp::config {

const double kDefaultStopTimeoutS = VOLCOMPD_DEFAULT_STOP_TIMEOUT_S;
const char* const kDaemonConfigKeysListedIn = "docs/daemon.md, Configuration reference";

namespace {

// A strictly positive number no larger than `max` (JsonReader::number takes closed ranges).
double positiveNumber(const JsonReader& value, double max) {
  const double v = value.number();
  if (!(v > 0.0) || v > max) value.failExpected("a number in (0, " + format::general(max) + "]");
  return v;
}

// A per-axis limit: one number for every axis, or {"X": x, "Y": y, "Z": z}. `read` checks one
// number and returns it.
template <typename Read>
std::array<double, 3> perAxis(const JsonReader& value, Read&& read) {
  if (!value.isObject()) {
    const double v = read(value);
    return {v, v, v};
  }
  value.allowOnly({"X", "Y", "Z"});
  return {read(value.at("X")), read(value.at("Y")), read(value.at("Z"))};
}

std::string resolveAgainst(const std::string& file, const std::string& relative) {
  const std::filesystem::path p(relative);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (std::filesystem::path(file).parent_path() / p).lexically_normal().string();
}

// Bounds that keep a configuration safe to run: an offset band no wider than a machine tool's
// compensation needs unless the file says so, and a stop that ends before systemd kills it.
void checkBounds(const JsonReader& root, const DaemonConfig& c) {
  const JsonReader limiter = root.at("limiter");
  double largestOffsetMm = 0.0;
  for (const loop::AxisLimits& a : c.limiter.axes) {
    largestOffsetMm = std::max(largestOffsetMm, a.maxOffsetMm);
  }
  if (largestOffsetMm > kMaxOffsetWithoutOverrideMm &&
      !limiter.booleanOr("allow_max_offset_above_2mm", false)) {
    limiter.at("max_offset_mm")
        .failExpected("at most " + format::general(kMaxOffsetWithoutOverrideMm) +
                      " mm (geometric compensation rarely needs more than tens of um; set "
                      "\"allow_max_offset_above_2mm\": true in \"limiter\" if this machine "
                      "really does)");
  }
  const double rampS = rampOutSeconds(c.limiter);
  const double stopS = 2.0 * rampS + 1.0;
  if (stopS > c.stopTimeoutS) {
    double slowestRateMmS = c.limiter.axes[0].maxRateMmS;
    for (const loop::AxisLimits& a : c.limiter.axes) {
      slowestRateMmS = std::min(slowestRateMmS, a.maxRateMmS);
    }
    // One line: the stop's bound (2 x ramp-out + 1 s) and TimeoutStopSec are in docs/daemon.md.
    limiter.fail("the ramp-out takes up to " + format::general(rampS) + " s, a stop up to " +
                 format::general(stopS) + " s: more than stop_timeout_s " +
                 format::general(c.stopTimeoutS) +
                 " s (TimeoutStopSec), systemd would kill the daemon with offsets applied. Raise "
                 "max_rate_mm_s to >= " +
                 format::general(2.0 * largestOffsetMm / (c.stopTimeoutS - 1.0), 3) +
                 " mm/s, lower max_offset_mm, or raise TimeoutStopSec and stop_timeout_s");
  }
}

}  // namespace

double rampOutSeconds(const loop::LimiterSettings& limiter) noexcept {
  std::array<double, 3> largestMm{};
  for (std::size_t k = 0; k < 3; ++k) largestMm[k] = limiter.axes[k].maxOffsetMm;
  return loop::rampOutSeconds(limiter, largestMm);
}

DaemonConfig parseDaemonConfig(const nlohmann::json& document, const std::string& file) {
  const JsonReader root(document, file);
  root.allowOnly({"cycle_period_ms",
                  "position_semantics",
                  "limiter",
                  "stale_timeout_ms",
                  "frozen_positions_are_stale",
                  "travel_margin_mm",
                  "direction_hysteresis_mm",
                  "offset_readback",
                  "plc_zero_after_ms",
                  "plc_heartbeat_timeout_ms",
                  "read_to_write_max_ms",
                  "fault_latch",
                  "service_watchdog_ms",
                  "model",
                  "reconnect",
                  "log_level",
                  "stop_timeout_s",
                  "accept_model_beyond_max_offset",
                  "latency_compensation",
                  "transport"},
                 kDaemonConfigKeysListedIn);
  DaemonConfig c;
  c.file = file;
  if (auto v = root.find("cycle_period_ms")) c.cyclePeriodMs = v->number(1.0, 1000.0);
  c.positionSemantics = root.at("position_semantics").oneOf({"commanded", "actual"}) == "actual"
                            ? loop::PositionSemantics::Actual
                            : loop::PositionSemantics::Commanded;

  const JsonReader limiter = root.at("limiter");
  limiter.allowOnly({"max_offset_mm", "max_rate_mm_s", "max_accel_mm_s2", "saturation_warning_ms",
                     "saturation_fault_ms", "allow_max_offset_above_2mm"});
  const auto offsets = perAxis(limiter.at("max_offset_mm"),
                               [](const JsonReader& v) { return positiveNumber(v, 100.0); });
  const auto rates = perAxis(limiter.at("max_rate_mm_s"),
                             [](const JsonReader& v) { return positiveNumber(v, 1000.0); });
  std::array<double, 3> accels{};
  if (auto v = limiter.find("max_accel_mm_s2")) {
    accels = perAxis(*v, [](const JsonReader& e) { return e.number(0.0, 1e6); });
  }
  for (std::size_t k = 0; k < 3; ++k) c.limiter.axes[k] = {offsets[k], rates[k], accels[k]};
  if (auto v = limiter.find("saturation_warning_ms")) c.saturationWarningMs = v->number(0.0, 3.6e6);
  if (auto v = limiter.find("saturation_fault_ms")) {
    c.saturationFaultMs = v->number(0.0, 3.6e6);
    if (c.saturationFaultMs > 0.0 && c.saturationFaultMs < c.saturationWarningMs) {
      v->failExpected("0 (no fault) or a time not shorter than limiter.saturation_warning_ms (" +
                      format::general(c.saturationWarningMs) + " ms)");
    }
  }
  c.faultLatch = root.booleanOr("fault_latch", true);

  if (auto v = root.find("stale_timeout_ms")) {
    c.staleTimeoutMs = v->number(0.0, 60000.0);
    if (!(c.staleTimeoutMs > c.cyclePeriodMs)) {
      v->failExpected("a timeout longer than cycle_period_ms (" + format::general(c.cyclePeriodMs) +
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

  // The PLC's heartbeat watchdog bounds how long a read-back stays true: a write must leave
  // before the PLC may have started removing the offsets it read.
  c.plcHeartbeatTimeoutMs = 5.0 * c.cyclePeriodMs;
  if (auto v = root.find("plc_heartbeat_timeout_ms")) {
    c.plcHeartbeatTimeoutMs = v->number(0.0, 600000.0);
    if (!(c.plcHeartbeatTimeoutMs > 2.0 * c.cyclePeriodMs)) {
      v->failExpected("a timeout longer than two cycle periods (" +
                      format::general(2.0 * c.cyclePeriodMs) + " ms)");
    }
  }
  c.readToWriteMaxMs = c.plcHeartbeatTimeoutMs / 2.0;
  if (auto v = root.find("read_to_write_max_ms")) {
    c.readToWriteMaxMs = positiveNumber(*v, 600000.0);
    if (c.readToWriteMaxMs + c.cyclePeriodMs >= c.plcHeartbeatTimeoutMs) {
      v->failExpected("less than plc_heartbeat_timeout_ms - cycle_period_ms (" +
                      format::general(c.plcHeartbeatTimeoutMs - c.cyclePeriodMs) +
                      " ms): the PLC could remove the offsets between a read and its write");
    }
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
  if (auto latency = root.find("latency_compensation")) {
    latency->allowOnly({"enabled", "controller_latency_ms"});
    c.latencyCompensation = latency->booleanOr("enabled", false);
    if (auto v = latency->find("controller_latency_ms"))
      c.controllerLatencyMs = v->number(0.0, 100.0);
  }
  if (auto v = root.find("log_level")) {
    c.logLevel = v->oneOf({"trace", "debug", "info", "warn", "error", "critical", "off"});
  }

  if (auto v = root.find("service_watchdog_ms")) c.serviceWatchdogMs = positiveNumber(*v, 3.6e6);
  if (auto v = root.find("stop_timeout_s")) c.stopTimeoutS = positiveNumber(*v, 3600.0);
  c.acceptModelBeyondMaxOffset = root.booleanOr("accept_model_beyond_max_offset", false);
  checkBounds(root, c);

  c.transport = parseTransportSettings(root.at("transport").json(), file, "transport");
  checkTransportLimits(c);
  return c;
}

DaemonConfig loadDaemonConfig(const std::string& path) {
  return parseDaemonConfig(readJsonFile(path), path);
}

std::optional<OffsetBound> offsetBoundOf(const DaemonConfig& config) {
  if (config.acceptModelBeyondMaxOffset) return std::nullopt;
  OffsetBound bound;
  for (std::size_t k = 0; k < 3; ++k) bound.maxOffsetMm[k] = config.limiter.axes[k].maxOffsetMm;
  bound.source = "limiter.max_offset_mm of " + config.file;
  return bound;
}

}  // namespace volcomp::config
