// volcomp-sim's configuration with a CAN transport: the example pair (sim-vmc-can.json and
// volcompd-can.json) resolves with the daemon's rules and agrees, the offset quantum of the
// limit check comes from the offset signals, and errors name the file and the key path.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/sim/sim_config.hpp"

namespace volcomp::sim {
namespace {

using nlohmann::json;

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

json example(const std::string& name) {
  std::ifstream in(kExamples + "/" + name);
  return json::parse(in);
}

TEST(SimCanConfig, TheExampleResolvesWithTheDaemonsLayout) {
  const SimConfig c = loadSimConfig(kExamples + "/sim-vmc-can.json");
  EXPECT_EQ(config::transportType(c.transport), "can");
  const auto* layout = std::get_if<can::CanLayout>(&c.transport);
  ASSERT_NE(layout, nullptr);
  EXPECT_EQ(layout->interfaceName, "vcan0");
  EXPECT_EQ(layout->trigger, can::Trigger::Broadcast);
  // Positions (0x100), Z with the flags (0x101), the read-back (0x102); offsets + status
  // (0x300) and the heartbeat (0x301), as in vmc-can.dbc.
  ASSERT_EQ(layout->inputFrames.size(), 3u);
  EXPECT_EQ(layout->inputFrames[0].id, 0x100u);
  ASSERT_EQ(layout->outputFrames.size(), 2u);
  EXPECT_EQ(layout->outputFrames[0].id, 0x300u);
  EXPECT_TRUE(layout->hasSequence);
  EXPECT_TRUE(layout->hasAppliedOffsets);
  // Off_X/Y/Z are int16 with scale 0.0001 mm: one count is 0.1 µm.
  for (double q : c.machine.limits.quantumMm) EXPECT_DOUBLE_EQ(q, 0.0001);
  EXPECT_DOUBLE_EQ(c.canBroadcastS, 0.001);
}

TEST(SimCanConfig, TheExamplePairSharesOneTransportSection) {
  EXPECT_EQ(example("sim-vmc-can.json")["transport"], example("volcompd-can.json")["transport"]);
  // And the limits the simulator checks are the daemon's limiter and cycle period.
  const json sim = example("sim-vmc-can.json");
  const json daemon = example("volcompd-can.json");
  EXPECT_EQ(sim["limits"]["max_offset_mm"], daemon["limiter"]["max_offset_mm"]);
  EXPECT_EQ(sim["limits"]["max_rate_mm_s"], daemon["limiter"]["max_rate_mm_s"]);
  EXPECT_EQ(sim["limits"]["cycle_ms"], daemon["cycle_period_ms"]);
}

TEST(SimCanConfig, FloatOffsetsHaveNoQuantum) {
  json doc = example("sim-vmc-can.json");
  auto sig = [](int id, int start, int length, const char* type, double scale) {
    return json{
        {"id", id}, {"start_bit", start}, {"length", length}, {"type", type}, {"scale", scale}};
  };
  // Inputs from the DBC as in the example; inline outputs: X, Y float32 (mm), Z int16 in µm.
  doc["transport"]["outputs"] = {{"offset",
                                  {{"X", sig(0x310, 0, 32, "float32", 1)},
                                   {"Y", sig(0x310, 32, 32, "float32", 1)},
                                   {"Z", sig(0x311, 0, 16, "signed", 0.001)}}},
                                 {"status", sig(0x311, 16, 16, "unsigned", 1)},
                                 {"heartbeat", sig(0x311, 32, 8, "unsigned", 1)}};
  const SimConfig c = parseSimConfig(doc, kExamples + "/sim.json");
  EXPECT_EQ(c.machine.limits.quantumMm[0], 0.0);
  EXPECT_EQ(c.machine.limits.quantumMm[1], 0.0);
  EXPECT_DOUBLE_EQ(c.machine.limits.quantumMm[2], 0.001);
}

TEST(SimCanConfig, ErrorsNameTheFileAndTheKeyPath) {
  json doc = example("sim-vmc-can.json");
  doc["transport"]["outputs"]["offset"]["Y"] = {{"dbc", "No_Such_Signal"}};
  try {
    parseSimConfig(doc, kExamples + "/sim.json");
    FAIL() << "an unknown DBC signal was accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), kExamples + "/sim.json");
    EXPECT_EQ(e.keyPath(), "transport.outputs.offset.Y.dbc") << e.what();
  }
  doc = example("sim-vmc.json");  // Modbus
  doc["can_broadcast_ms"] = 2;
  try {
    parseSimConfig(doc, "sim.json");
    FAIL() << "can_broadcast_ms accepted with Modbus";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "can_broadcast_ms");
  }
  doc = example("sim-vmc-can.json");
  doc["can_broadcast_ms"] = 0.0;
  try {
    parseSimConfig(doc, kExamples + "/sim.json");
    FAIL() << "can_broadcast_ms 0 accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "can_broadcast_ms") << e.what();
  }
}

}  // namespace
}  // namespace volcomp::sim
