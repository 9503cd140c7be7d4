// The daemon configuration: a valid file, defaults, and one test per class of rejection, each
// checking the file and key path the message names.
#include "volcomp/config/daemon_config.hpp"

#include <gtest/gtest.h>

#include <string>

#include "temp_files.hpp"
#include "volcomp/daemon/configuration.hpp"

namespace volcomp::config {
namespace {

using loop::PositionSemantics;
using nlohmann::json;

json minimal() {
  return json::parse(R"({
    "position_semantics": "commanded",
    "limiter": {"max_offset_mm": 0.5, "max_rate_mm_s": 1.0},
    "model": "model.json",
    "transport": {"type": "modbus-tcp", "host": "127.0.0.1", "port": 1502, "registers": {
      "position": {"X": {"address": 0}, "Y": {"address": 2}, "Z": {"address": 4}},
      "enable": {"address": 6, "bit": 0}, "homed": {"address": 6, "bit": 1},
      "offset": {"X": {"address": 8}, "Y": {"address": 10}, "Z": {"address": 12}},
      "status": 14, "heartbeat": 15}}
  })");
}

/// A CAN section with one input frame (0x100) and two output frames (0x300, 0x301).
json canTransport() {
  return json::parse(R"({"type": "can", "interface": "can0", "trigger": "broadcast",
    "inputs": {
      "position": {
        "X": {"id": 256, "start_bit": 0, "length": 16, "type": "signed", "scale": 0.001},
        "Y": {"id": 256, "start_bit": 16, "length": 16, "type": "signed", "scale": 0.001},
        "Z": {"id": 256, "start_bit": 32, "length": 16, "type": "signed", "scale": 0.001}},
      "enable": {"id": 256, "start_bit": 48, "length": 1},
      "homed": {"id": 256, "start_bit": 49, "length": 1}},
    "outputs": {
      "offset": {
        "X": {"id": 768, "start_bit": 0, "length": 16, "type": "signed", "scale": 0.001},
        "Y": {"id": 768, "start_bit": 16, "length": 16, "type": "signed", "scale": 0.001},
        "Z": {"id": 768, "start_bit": 32, "length": 16, "type": "signed", "scale": 0.001}},
      "status": {"id": 768, "start_bit": 48, "length": 16},
      "heartbeat": {"id": 769, "start_bit": 0, "length": 8}}})");
}

// Expects a ConfigError at `path` whose message contains `fragment`.
void expectError(const json& doc, const std::string& path, const std::string& fragment) {
  try {
    parseDaemonConfig(doc, "/etc/volcomp/daemon.json");
    FAIL() << "accepted; expected an error at " << path;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "/etc/volcomp/daemon.json");
    EXPECT_EQ(e.keyPath(), path) << e.what();
    EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
  }
}

// The one line a refused file gives, for checks of its length.
std::string refusalOf(const json& doc) {
  try {
    parseDaemonConfig(doc, "/etc/volcomp/volcompd.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return {};
}

TEST(DaemonConfig, MinimalFileGetsTheDefaults) {
  const DaemonConfig c = parseDaemonConfig(minimal(), "/etc/volcomp/daemon.json");
  EXPECT_EQ(c.file, "/etc/volcomp/daemon.json");
  EXPECT_DOUBLE_EQ(c.cyclePeriodMs, 10.0);
  EXPECT_EQ(c.positionSemantics, PositionSemantics::Commanded);
  for (const loop::AxisLimits& axis : c.limiter.axes) {
    EXPECT_DOUBLE_EQ(axis.maxOffsetMm, 0.5);
    EXPECT_DOUBLE_EQ(axis.maxRateMmS, 1.0);
    EXPECT_DOUBLE_EQ(axis.maxAccelMmS2, 0.0);
  }
  EXPECT_DOUBLE_EQ(c.staleTimeoutMs, 500.0);
  EXPECT_FALSE(c.frozenPositionsAreStale);
  EXPECT_DOUBLE_EQ(c.travelMarginMm, 1.0);
  EXPECT_TRUE(c.offsetReadback);
  EXPECT_FALSE(c.plcZeroAfterMs.has_value());
  EXPECT_EQ(c.modelPath, "/etc/volcomp/model.json");  // relative to the config file
  EXPECT_DOUBLE_EQ(c.reconnect.initialMs, 100.0);
  EXPECT_DOUBLE_EQ(c.reconnect.maxMs, 2000.0);
  EXPECT_EQ(c.logLevel, "info");
  EXPECT_FALSE(c.latencyCompensation);
  EXPECT_DOUBLE_EQ(c.controllerLatencyMs, 0.0);
  EXPECT_EQ(transportType(c.transport), "modbus-tcp");
  // Read into the driver's settings.
  const auto& settings = std::get<modbus::ModbusSettings>(c.transport);
  EXPECT_EQ(std::get<modbus::TcpLink>(settings.link).port, 1502);
  EXPECT_EQ(settings.registers.heartbeatAddress, 15);
}

TEST(DaemonConfig, EveryKeyIsRead) {
  json doc = json::parse(R"({
    "cycle_period_ms": 4, "position_semantics": "actual",
    "limiter": {"max_offset_mm": 0.2, "max_rate_mm_s": 2, "max_accel_mm_s2": 50},
    "stale_timeout_ms": 40, "frozen_positions_are_stale": true, "travel_margin_mm": 0.5,
    "direction_hysteresis_mm": 0.01, "offset_readback": false, "plc_zero_after_ms": 300,
    "model": "/opt/models/m.json", "reconnect": {"initial_ms": 50, "max_ms": 1000},
    "log_level": "debug"
  })");
  doc["transport"] = canTransport();
  const DaemonConfig c = parseDaemonConfig(doc, "conf/d.json");
  EXPECT_DOUBLE_EQ(c.cyclePeriodMs, 4.0);
  EXPECT_EQ(c.positionSemantics, PositionSemantics::Actual);
  for (const loop::AxisLimits& axis : c.limiter.axes) EXPECT_DOUBLE_EQ(axis.maxAccelMmS2, 50.0);
  EXPECT_DOUBLE_EQ(c.staleTimeoutMs, 40.0);
  EXPECT_TRUE(c.frozenPositionsAreStale);
  EXPECT_DOUBLE_EQ(c.travelMarginMm, 0.5);
  EXPECT_DOUBLE_EQ(c.directionHysteresisMm, 0.01);
  EXPECT_FALSE(c.offsetReadback);
  EXPECT_DOUBLE_EQ(*c.plcZeroAfterMs, 300.0);
  EXPECT_EQ(c.modelPath, "/opt/models/m.json");  // absolute stays
  EXPECT_DOUBLE_EQ(c.reconnect.initialMs, 50.0);
  EXPECT_DOUBLE_EQ(c.reconnect.maxMs, 1000.0);
  EXPECT_EQ(c.logLevel, "debug");
  EXPECT_EQ(transportType(c.transport), "can");
  EXPECT_EQ(std::get<can::CanLayout>(c.transport).interfaceName, "can0");
}

TEST(DaemonConfig, LatencyCompensationIsReadIntoTheLoopSettings) {
  json doc = minimal();
  doc["latency_compensation"] = {{"enabled", true}, {"controller_latency_ms", 1.5}};
  const DaemonConfig c = parseDaemonConfig(doc, "/etc/volcomp/daemon.json");
  EXPECT_TRUE(c.latencyCompensation);
  EXPECT_DOUBLE_EQ(c.controllerLatencyMs, 1.5);
  const loop::LoopSettings s = daemon::loopSettingsFrom(c);
  EXPECT_TRUE(s.latencyCompensation);
  EXPECT_EQ(s.controllerLatency, std::chrono::microseconds(1500));

  doc["latency_compensation"] = {{"enabled", "yes"}};
  expectError(doc, "latency_compensation.enabled", "expected");
  doc["latency_compensation"] = {{"enabled", true}, {"controller_latency_ms", -1}};
  expectError(doc, "latency_compensation.controller_latency_ms", "expected");
  doc["latency_compensation"] = {{"enabled", true}, {"controller_latency_ms", 500}};
  expectError(doc, "latency_compensation.controller_latency_ms", "100");
  doc["latency_compensation"] = {{"on", true}};
  expectError(doc, "latency_compensation.on", "unknown key");
  doc["latency_compensation"] = true;
  expectError(doc, "latency_compensation", "expected");
}

TEST(DaemonConfig, TransportErrorsNameTheDaemonFileAndTheTransportKeyPath) {
  json doc = minimal();
  doc["transport"]["registers"]["heartbeat"] = 4;  // on position Z
  expectError(doc, "transport.registers.heartbeat", "overlaps");
  doc = minimal();
  doc["transport"] = canTransport();
  doc["transport"]["outputs"]["status"]["length"] = 8;
  expectError(doc, "transport.outputs.status", "16 bits");
}

TEST(DaemonConfig, RejectsUnknownKeys) {
  json doc = minimal();
  doc["cycle_period"] = 10;
  expectError(doc, "cycle_period", "unknown key");
  doc = minimal();
  doc["limiter"]["max_speed"] = 1;
  expectError(doc, "limiter.max_speed", "unknown key");
  doc = minimal();
  doc["reconnect"] = {{"initial", 100}};
  expectError(doc, "reconnect.initial", "unknown key");
}

TEST(DaemonConfig, RejectsMissingRequiredKeys) {
  for (const char* key : {"position_semantics", "limiter", "model", "transport"}) {
    json doc = minimal();
    doc.erase(key);
    expectError(doc, key, "missing");
  }
  json doc = minimal();
  doc["limiter"].erase("max_rate_mm_s");
  expectError(doc, "limiter.max_rate_mm_s", "missing");
  doc = minimal();
  doc["transport"].erase("type");
  expectError(doc, "transport.type", "missing");
}

TEST(DaemonConfig, RejectsWrongTypes) {
  json doc = minimal();
  doc["cycle_period_ms"] = "10";
  expectError(doc, "cycle_period_ms", "expected");
  doc = minimal();
  doc["offset_readback"] = 1;
  expectError(doc, "offset_readback", "expected");
  doc = minimal();
  doc["model"] = json::array({"a.json"});
  expectError(doc, "model", "expected");
  doc = minimal();
  doc["transport"] = "modbus-tcp";
  expectError(doc, "transport", "expected");
}

TEST(DaemonConfig, RejectsOutOfRangeNumbers) {
  json doc = minimal();
  doc["cycle_period_ms"] = 0;
  expectError(doc, "cycle_period_ms", "expected");
  doc = minimal();
  doc["limiter"]["max_offset_mm"] = 0;
  expectError(doc, "limiter.max_offset_mm", "(0, 100]");
  doc = minimal();
  doc["limiter"]["max_rate_mm_s"] = -1;
  expectError(doc, "limiter.max_rate_mm_s", "expected");
  doc = minimal();
  doc["limiter"]["max_accel_mm_s2"] = -5;
  expectError(doc, "limiter.max_accel_mm_s2", "expected");
  doc = minimal();
  doc["travel_margin_mm"] = -0.1;
  expectError(doc, "travel_margin_mm", "expected");
}

TEST(DaemonConfig, RejectsUnknownChoices) {
  json doc = minimal();
  doc["position_semantics"] = "programmed";
  expectError(doc, "position_semantics", "commanded");
  doc = minimal();
  doc["transport"]["type"] = "profibus";
  expectError(doc, "transport.type", "modbus-tcp");
  doc = minimal();
  doc["log_level"] = "verbose";
  expectError(doc, "log_level", "info");
}

TEST(DaemonConfig, RejectsInconsistentCombinations) {
  json doc = minimal();
  doc["cycle_period_ms"] = 50;
  doc["stale_timeout_ms"] = 50;
  expectError(doc, "stale_timeout_ms", "longer than cycle_period_ms");
  doc = minimal();
  doc["cycle_period_ms"] = 600;  // the 500 ms default stale timeout would be shorter
  expectError(doc, "", "stale_timeout_ms");
  doc = minimal();
  doc["reconnect"] = {{"initial_ms", 500}, {"max_ms", 100}};
  expectError(doc, "reconnect.max_ms", "initial_ms");
  doc = minimal();
  doc["offset_readback"] = false;
  expectError(doc, "plc_zero_after_ms", "missing");
}

TEST(DaemonConfig, LimitsPerAxis) {
  json doc = minimal();
  doc["limiter"] = json::parse(R"({"max_offset_mm": {"X": 0.1, "Y": 0.2, "Z": 0.05},
    "max_rate_mm_s": 0.5, "max_accel_mm_s2": {"X": 10, "Y": 20, "Z": 0}})");
  const DaemonConfig c = parseDaemonConfig(doc, "d.json");
  EXPECT_EQ(c.limiter.axes[0], (loop::AxisLimits{0.1, 0.5, 10.0}));
  EXPECT_EQ(c.limiter.axes[1], (loop::AxisLimits{0.2, 0.5, 20.0}));
  EXPECT_EQ(c.limiter.axes[2], (loop::AxisLimits{0.05, 0.5, 0.0}));
  doc["limiter"]["max_rate_mm_s"] = {{"X", 1}, {"Y", 1}};
  expectError(doc, "limiter.max_rate_mm_s.Z", "missing");
  doc["limiter"]["max_rate_mm_s"] = {{"X", 1}, {"Y", 1}, {"Z", 1}, {"A", 1}};
  expectError(doc, "limiter.max_rate_mm_s.A", "unknown key");
  doc["limiter"]["max_rate_mm_s"] = {{"X", 1}, {"Y", 0}, {"Z", 1}};
  expectError(doc, "limiter.max_rate_mm_s.Y", "(0, 1000]");
}

TEST(DaemonConfig, TimingSafetyKeysAndTheirDefaults) {
  DaemonConfig c = parseDaemonConfig(minimal(), "d.json");
  // The PLC's heartbeat timeout defaults to five periods, the read-to-write bound to half of it.
  EXPECT_DOUBLE_EQ(c.plcHeartbeatTimeoutMs, 50.0);
  EXPECT_DOUBLE_EQ(c.readToWriteMaxMs, 25.0);
  EXPECT_DOUBLE_EQ(c.saturationWarningMs, 1000.0);
  EXPECT_DOUBLE_EQ(c.saturationFaultMs, 10000.0);
  EXPECT_TRUE(c.faultLatch);
  json doc = minimal();
  doc["plc_heartbeat_timeout_ms"] = 300;
  doc["limiter"]["saturation_warning_ms"] = 200;
  doc["limiter"]["saturation_fault_ms"] = 0;
  doc["fault_latch"] = false;
  c = parseDaemonConfig(doc, "d.json");
  EXPECT_DOUBLE_EQ(c.readToWriteMaxMs, 150.0);
  EXPECT_DOUBLE_EQ(c.saturationWarningMs, 200.0);
  EXPECT_DOUBLE_EQ(c.saturationFaultMs, 0.0);
  EXPECT_FALSE(c.faultLatch);
  doc["read_to_write_max_ms"] = 40;
  EXPECT_DOUBLE_EQ(parseDaemonConfig(doc, "d.json").readToWriteMaxMs, 40.0);
}

TEST(DaemonConfig, RejectsTimingThatLetsThePlcActBetweenReadAndWrite) {
  json doc = minimal();
  doc["plc_heartbeat_timeout_ms"] = 100;
  doc["read_to_write_max_ms"] = 95;  // + one 10 ms period >= the PLC's timeout
  expectError(doc, "read_to_write_max_ms", "plc_heartbeat_timeout_ms");
  doc = minimal();
  doc["plc_heartbeat_timeout_ms"] = 20;  // two periods: the PLC would trip on one late cycle
  expectError(doc, "plc_heartbeat_timeout_ms", "two cycle periods");
  doc = minimal();
  doc["limiter"]["saturation_warning_ms"] = 5000;
  doc["limiter"]["saturation_fault_ms"] = 1000;
  expectError(doc, "limiter.saturation_fault_ms", "saturation_warning_ms");
}

TEST(DaemonConfig, RejectsNonFiniteNumbers) {
  json doc = minimal();
  doc["limiter"]["max_offset_mm"] = std::numeric_limits<double>::quiet_NaN();
  expectError(doc, "limiter.max_offset_mm", "");
}

TEST(DaemonConfig, FileErrorsNameTheFile) {
  volcomp::testing::TempDir dir;
  const std::string missing = (dir.path() / "absent.json").string();
  try {
    loadDaemonConfig(missing);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), missing);
  }
  const std::string bad = dir.write("bad.json", "{\"model\": \"m.json\",,}");
  try {
    loadDaemonConfig(bad);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), bad);
    EXPECT_NE(std::string(e.what()).find("line"), std::string::npos) << e.what();
  }
  const std::string good = dir.write("good.json", minimal().dump());
  EXPECT_EQ(loadDaemonConfig(good).modelPath, (dir.path() / "model.json").string());
}

// An unknown key among the file's twenty is one line: the file, the key, the key it most likely
// meant and where the keys are listed, not the list itself.
TEST(DaemonConfig, AnUnknownKeyNamesTheClosestKeyAndWhereTheKeysAreListed) {
  json doc = minimal();
  doc["cycle_perod_ms"] = 10;
  expectError(doc, "cycle_perod_ms", "unknown key; did you mean \"cycle_period_ms\"?");
  const std::string line = refusalOf(doc);
  EXPECT_EQ(line.rfind("/etc/volcomp/volcompd.json: cycle_perod_ms: unknown key", 0), 0u) << line;
  EXPECT_NE(line.find("docs/daemon.md, Configuration reference"), std::string::npos) << line;
  EXPECT_EQ(line.find("position_semantics"), std::string::npos) << line;
  EXPECT_LE(line.size(), 300u) << line;
}

// The longest refusals of the file stay one line under 300 characters: a ramp-out that does not
// fit the stop timeout, invalid JSON with a long token.
TEST(DaemonConfig, LongRefusalsAreOneShortLine) {
  json slow = minimal();
  slow["limiter"]["max_rate_mm_s"] = 0.01;  // 0.5 mm: a 50 s ramp-out
  expectError(slow, "limiter", "the ramp-out takes up to 50 s");
  const std::string ramp = refusalOf(slow);
  EXPECT_NE(ramp.find("TimeoutStopSec"), std::string::npos) << ramp;
  EXPECT_LE(ramp.size(), 300u) << ramp;

  volcomp::testing::TempDir dir;
  const std::string path =
      dir.write("volcompd.json", "{\"log_level\": \"" + std::string(3000, 'i') + "\t\"}");
  try {
    loadDaemonConfig(path);
    FAIL();
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + ": invalid JSON: parse error at line 1, column ", 0), 0u) << what;
    EXPECT_LE(what.size(), 300u) << what;
  }
}

// A calibrated model records the tools it was measured with; the daemon compensates for the
// model's own tool and warns (start and reload) when that one was never measured.
TEST(DaemonConfig, AModelToolFarFromTheCalibratedToolsIsAWarning) {
  volcomp::testing::TempDir dir;
  json model = json::parse(R"({"format": "volcomp-model/1", "topology": "XYFZ",
    "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
    "error_units": {"length": "um", "angle": "urad"}, "components": {"EBX": 12}})");
  const auto load = [&](const json& m) {
    std::vector<std::string> warnings;
    const auto compensation =
        daemon::loadCompensationModel(dir.write("m.json", m.dump()), std::nullopt, &warnings);
    EXPECT_NE(compensation, nullptr);
    return warnings;
  };
  EXPECT_TRUE(load(model).empty());  // no calibration block: nothing to compare with
  model["calibration"] = {{"tools_mm", {{0, 0, 100}, {0, 0, 200}}}};
  EXPECT_TRUE(load(model).empty());  // 120 mm lies between the measured lengths
  model["tool"] = {0, 0, 250};
  const std::vector<std::string> warnings = load(model);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("its tool (0, 0, 250) mm is 50 mm outside the tools the model was "
                             "calibrated with, (0, 0, 100); (0, 0, 200) mm"),
            std::string::npos)
      << warnings[0];
  model["tool"] = {0, 0, 205};  // within the 10 mm tolerance
  EXPECT_TRUE(load(model).empty());

  json daemonFile = minimal();
  model["tool"] = {0, 0, 250};
  dir.write("model.json", model.dump());
  const std::string configPath = dir.write("daemon.json", daemonFile.dump());
  EXPECT_EQ(daemon::loadConfiguration(configPath).warnings.size(), 1u);
}

}  // namespace
}  // namespace volcomp::config
