#include "volcomp/sim/sim_config.hpp"

#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/json_reader.hpp"

namespace volcomp::sim {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

json example(const std::string& name) {
  return json::parse(std::ifstream(kExamples + "/" + name));
}

void expectRejected(const json& doc, const std::string& keyPath, const std::string& message) {
  try {
    parseSimConfig(doc, "sim.json");
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), keyPath) << e.what();
    EXPECT_THAT(e.message(), HasSubstr(message)) << e.what();
  }
}

TEST(SimConfig, TheExampleMatchesTheDaemonExample) {
  const SimConfig sim = loadSimConfig(kExamples + "/sim-vmc.json");
  const config::DaemonConfig daemon =
      config::loadDaemonConfig(kExamples + "/volcompd-modbus-tcp.json");
  ASSERT_TRUE(std::holds_alternative<modbus::ModbusSettings>(sim.transport));
  EXPECT_EQ(config::transportType(sim.transport), "modbus-tcp");
  EXPECT_TRUE(sim.transport == daemon.transport) << "the same transport section on both sides";
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(sim.machine.limits.maxOffsetMm[k], daemon.limiter.axes[k].maxOffsetMm);
    EXPECT_EQ(sim.machine.limits.maxRateMmS[k], daemon.limiter.axes[k].maxRateMmS);
  }
  EXPECT_DOUBLE_EQ(sim.machine.limits.cycleS * 1000.0, daemon.cyclePeriodMs);
  EXPECT_EQ(sim.machine.semantics, daemon.positionSemantics);
  // int32 at 10000 counts/mm: one count is 0.1 um.
  EXPECT_DOUBLE_EQ(sim.machine.limits.quantumMm[0], 1e-4);
  ASSERT_TRUE(sim.modelPath.has_value());
  EXPECT_EQ(*sim.modelPath, kExamples + "/vmc-xyfz-21-true.json");
  const Path path = makePath(sim.path);
  EXPECT_GT(path.lengthMm(), 0.0);
  // The RTU example carries the same register map.
  const config::DaemonConfig rtu =
      config::loadDaemonConfig(kExamples + "/volcompd-modbus-rtu.json");
  EXPECT_TRUE(std::get<modbus::ModbusSettings>(rtu.transport).registers ==
              std::get<modbus::ModbusSettings>(daemon.transport).registers);
}

TEST(SimConfig, PathKindsAndRejections) {
  json doc = example("sim-vmc.json");
  doc["path"] = {{"type", "points"}, {"points", {{0, 0, 0}, {10, 0, 0}}}, {"feed_mm_min", 600}};
  EXPECT_DOUBLE_EQ(makePath(parseSimConfig(doc, "sim.json").path).lengthMm(), 20.0);

  doc["path"] = {{"type", "spiral"}, {"feed_mm_min", 600}};
  expectRejected(doc, "path.type", "raster");
  doc["path"] = {{"type", "circle"}, {"center", {0, 0}}, {"radius_mm", 5}, {"feed_mm_min", 600}};
  expectRejected(doc, "path.center", "");
  doc["path"] = {{"type", "circle"}, {"center", {0, 0, 0}}, {"radius_mm", 5}, {"feed_mm_min", 0}};
  expectRejected(doc, "path.feed_mm_min", "");

  doc = example("sim-vmc.json");
  doc["limits"]["max_jerk"] = 1;
  expectRejected(doc, "limits.max_jerk", "unknown key");
  doc = example("sim-vmc.json");
  doc["position_semantics"] = "programmed";
  expectRejected(doc, "position_semantics", "commanded");
  doc = example("sim-vmc.json");
  doc["transport"]["registers"]["status"] = 3;
  expectRejected(doc, "transport.registers.status", "overlaps");
}

// The simulator reads a CAN section with the daemon's rules too: an incomplete one is rejected at
// its key path (tests/can/sim_can_config_test.cpp loads the complete example).
TEST(SimConfig, PositionScanAndTheTimestampTickFromTheRegisterMap) {
  json doc = example("sim-vmc.json");
  EXPECT_EQ(parseSimConfig(doc, "sim.json").machine.positionScanS, 0.0);
  EXPECT_EQ(parseSimConfig(doc, "sim.json").machine.timestampTickS, 0.0);
  doc["position_scan_ms"] = 4;
  doc["transport"]["registers"]["timestamp"] = {{"address", 22}, {"tick_us", 10}};
  const SimConfig c = parseSimConfig(doc, "sim.json");
  EXPECT_DOUBLE_EQ(c.machine.positionScanS, 0.004);
  EXPECT_DOUBLE_EQ(c.machine.timestampTickS, 10e-6);
  doc["position_scan_ms"] = -1;
  expectRejected(doc, "position_scan_ms", "");
}

TEST(SimConfig, CanTransportIsReadWithTheDaemonsRules) {
  json doc = example("sim-vmc.json");
  doc["transport"] = {{"type", "can"}, {"interface", "vcan0"}};
  expectRejected(doc, "transport.trigger", "missing");
}

}  // namespace
}  // namespace volcomp::sim
