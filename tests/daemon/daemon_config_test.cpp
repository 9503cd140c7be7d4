// The daemon configuration: a valid file, defaults, and one test per class of rejection, each
// checking the file and key path the message names.
#include "volcomp/config/daemon_config.hpp"

#include <gtest/gtest.h>

#include <string>

#include "temp_files.hpp"

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

TEST(DaemonConfig, MinimalFileGetsTheDefaults) {
  const DaemonConfig c = parseDaemonConfig(minimal(), "/etc/volcomp/daemon.json");
  EXPECT_EQ(c.file, "/etc/volcomp/daemon.json");
  EXPECT_DOUBLE_EQ(c.cyclePeriodMs, 10.0);
  EXPECT_EQ(c.positionSemantics, PositionSemantics::Commanded);
  EXPECT_DOUBLE_EQ(c.limiter.maxOffsetMm, 0.5);
  EXPECT_DOUBLE_EQ(c.limiter.maxRateMmS, 1.0);
  EXPECT_DOUBLE_EQ(c.limiter.maxAccelMmS2, 0.0);
  EXPECT_DOUBLE_EQ(c.staleTimeoutMs, 500.0);
  EXPECT_FALSE(c.frozenPositionsAreStale);
  EXPECT_DOUBLE_EQ(c.travelMarginMm, 1.0);
  EXPECT_TRUE(c.offsetReadback);
  EXPECT_FALSE(c.plcZeroAfterMs.has_value());
  EXPECT_EQ(c.modelPath, "/etc/volcomp/model.json");  // relative to the config file
  EXPECT_DOUBLE_EQ(c.reconnect.initialMs, 100.0);
  EXPECT_DOUBLE_EQ(c.reconnect.maxMs, 2000.0);
  EXPECT_EQ(c.logLevel, "info");
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
  EXPECT_DOUBLE_EQ(c.limiter.maxAccelMmS2, 50.0);
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

}  // namespace
}  // namespace volcomp::config
