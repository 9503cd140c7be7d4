#include "volcomp/config/can_config.hpp"

#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "temp_files.hpp"
#include "volcomp/can/layout.hpp"

namespace volcomp::can {
namespace {

using config::loadCanLayout;
using nlohmann::json;

json sig(int id, int start, int length, const char* type = "signed", double scale = 0.0001) {
  return json{
      {"id", id}, {"start_bit", start}, {"length", length}, {"type", type}, {"scale", scale}};
}

/// A valid broadcast configuration: positions in 0x100 (X, Y) and 0x101 (Z, flags), each with an
/// 8-bit sequence counter in byte 7; outputs in 0x300 (3 x int16 offsets in µm, 16-bit status in
/// bytes 6..7) and 0x301 (heartbeat).
json baseConfig() {
  return json{{"type", "can"},
              {"interface", "vcan0"},
              {"trigger", "broadcast"},
              {"timeouts", {{"stale_ms", 50}}},
              {"inputs",
               {{"position",
                 {{"X", sig(0x100, 0, 24)}, {"Y", sig(0x100, 24, 24)}, {"Z", sig(0x101, 0, 32)}}},
                {"enable", sig(0x101, 32, 1, "unsigned", 1)},
                {"homed", sig(0x101, 33, 1, "unsigned", 1)},
                {"sequence", json::array({sig(0x100, 56, 8, "unsigned", 1),
                                          sig(0x101, 56, 8, "unsigned", 1)})}}},
              {"outputs",
               {{"offset",
                 {{"X", sig(0x300, 0, 16, "signed", 0.001)},
                  {"Y", sig(0x300, 16, 16, "signed", 0.001)},
                  {"Z", sig(0x300, 32, 16, "signed", 0.001)}}},
                {"status", sig(0x300, 48, 16, "unsigned", 1)},
                {"heartbeat", sig(0x301, 0, 8, "unsigned", 1)}}}};
}

TEST(CanConfig, ParsesAndResolvesABroadcastLayout) {
  const CanLayout layout = loadCanLayout(baseConfig(), "daemon.json", "transport");
  EXPECT_EQ(layout.interfaceName, "vcan0");
  EXPECT_FALSE(layout.fd);
  EXPECT_EQ(layout.trigger, can::Trigger::Broadcast);
  EXPECT_EQ(layout.staleTimeout, std::chrono::milliseconds(50));
  EXPECT_EQ(layout.responseTimeout, std::chrono::milliseconds(10));
  EXPECT_TRUE(layout.hasSequence);
  EXPECT_FALSE(layout.hasAppliedOffsets);
  ASSERT_EQ(layout.inputFrames.size(), 2u);
  EXPECT_EQ(layout.inputFrames[0].id, 0x100u);
  EXPECT_EQ(layout.inputFrames[0].length, 8u);  // sequence counter ends in byte 7
  EXPECT_EQ(layout.inputFrames[0].signals.size(), 3u);
  ASSERT_EQ(layout.outputFrames.size(), 2u);
  EXPECT_EQ(layout.outputFrames[0].length, 8u);
  EXPECT_EQ(layout.outputFrames[1].length, 1u);
  EXPECT_FALSE(layout.syncFrame.has_value());
}

TEST(CanConfig, SyncTriggerNeedsASyncFrame) {
  json c = baseConfig();
  c["trigger"] = "sync";
  c["sync"] = {{"id", "0x80"}, {"data", {1, 2}}};
  const CanLayout layout = loadCanLayout(c, "daemon.json", "transport");
  ASSERT_TRUE(layout.syncFrame.has_value());
  EXPECT_EQ(layout.syncFrame->id, 0x80u);
  EXPECT_EQ(layout.syncFrame->length, 2u);

  c.erase("sync");
  EXPECT_THROW(loadCanLayout(c, "daemon.json", "transport"), config::ConfigError);
}

void expectErrorIn(const json& c, const std::string& file, const std::string& keyPath,
                   const std::string& part) {
  try {
    loadCanLayout(c, file, "transport");
    FAIL() << "accepted: " << c.dump();
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), file);
    EXPECT_EQ(e.keyPath(), keyPath) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

void expectError(const json& c, const std::string& keyPath, const std::string& part) {
  expectErrorIn(c, "daemon.json", keyPath, part);
}

TEST(CanConfig, RejectsBadFieldsWithKeyPaths) {
  json c = baseConfig();
  c["inputs"]["position"]["X"]["id"] = 0x800;
  expectError(c, "transport.inputs.position.X.id", "11-bit");

  c = baseConfig();
  c["inputs"]["position"]["X"]["id"] = "0xZZ";
  expectError(c, "transport.inputs.position.X.id", "identifier");

  c = baseConfig();
  c["inputs"]["position"]["X"]["length"] = 65;
  expectError(c, "transport.inputs.position.X.length", "");

  c = baseConfig();
  c["inputs"]["position"]["X"]["byte_order"] = "middle";
  expectError(c, "transport.inputs.position.X.byte_order", "");

  c = baseConfig();
  c["inputs"]["position"]["X"]["scale"] = 0;
  expectError(c, "transport.inputs.position.X.scale", "non-zero");

  c = baseConfig();
  c["inputs"]["position"]["X"]["colour"] = 1;
  expectError(c, "transport.inputs.position.X.colour", "unknown key");

  c = baseConfig();
  c["trigger"] = "sometimes";
  expectError(c, "transport.trigger", "");

  c = baseConfig();
  c["interface"] = "a-very-long-interface-name";
  expectError(c, "transport.interface", "1 to 15");

  c = baseConfig();
  c["sync"] = {{"id", 1}};
  expectError(c, "transport.sync", "only used");
}

TEST(CanConfig, RejectsBadLayouts) {
  json c = baseConfig();
  c["inputs"]["position"]["Y"]["start_bit"] = 16;  // overlaps X (bits 0..23)
  expectError(c, "transport.inputs.position.Y", "overlaps transport.inputs.position.X");

  c = baseConfig();
  c["inputs"]["sequence"] = sig(0x100, 56, 8, "unsigned", 1);
  expectError(c, "transport.inputs.sequence", "frame 0x101 has none");

  c = baseConfig();
  c["outputs"]["status"]["length"] = 8;
  expectError(c, "transport.outputs.status", "at least 16 bits");

  c = baseConfig();
  c["outputs"]["heartbeat"]["scale"] = 2;
  expectError(c, "transport.outputs.heartbeat", "counter");

  c = baseConfig();
  c["outputs"]["heartbeat"]["id"] = 0x101;
  expectError(c, "transport.outputs.heartbeat", "both an input and an output");

  c = baseConfig();
  c["inputs"]["position"]["Z"]["start_bit"] = 40;  // bits 40..71: beyond 8 bytes
  c["inputs"]["enable"]["start_bit"] = 34;
  expectError(c, "transport.inputs.position.Z", "more than a classical CAN frame");

  c = baseConfig();
  c["inputs"]["position"]["Z"]["type"] = "float32";
  c["inputs"]["position"]["Z"]["length"] = 16;
  expectError(c, "transport.inputs.position.Z", "32 bits");

  c = baseConfig();
  c["trigger"] = "sync";
  c["sync"] = {{"id", 0x100}};
  expectError(c, "transport.sync.id", "also an input");
}

TEST(CanConfig, FdAllowsLongFramesRoundedToValidLengths) {
  json c = baseConfig();
  c["fd"] = true;
  c["inputs"]["position"]["Z"] = sig(0x101, 64, 32);             // bytes 8..11
  c["outputs"]["heartbeat"] = sig(0x300, 72, 8, "unsigned", 1);  // byte 9: frame of 10 -> 12
  const CanLayout layout = loadCanLayout(c, "daemon.json", "transport");
  EXPECT_TRUE(layout.fd);
  ASSERT_EQ(layout.outputFrames.size(), 1u);
  EXPECT_EQ(layout.outputFrames[0].length, 12u);
  EXPECT_EQ(layout.inputFrames[1].length, 12u);
}

using volcomp::testing::TempDir;

constexpr const char* kMachineDbc = R"(BO_ 256 Positions: 8 PLC
 SG_ X_Pos : 7|32@0- (0.0001,0) [-2000|2000] "mm" VOLCOMP
 SG_ Y_Pos : 39|32@0- (0.0001,0) [-2000|2000] "mm" VOLCOMP
BO_ 257 Axis_Z: 8 PLC
 SG_ Z_Pos : 0|32@1- (0.0001,0) [-2000|2000] "mm" VOLCOMP
 SG_ Enable : 32|1@1+ (1,0) [0|1] "" VOLCOMP
 SG_ Homed : 33|1@1+ (1,0) [0|1] "" VOLCOMP
 SG_ Mux M : 40|8@1+ (1,0) [0|0] "" VOLCOMP
BO_ 768 Offsets: 8 VOLCOMP
 SG_ Off_X : 0|16@1- (0.001,0) [-1|1] "mm" PLC
 SG_ Off_Y : 16|16@1- (0.001,0) [-1|1] "mm" PLC
 SG_ Off_Z : 32|16@1- (0.001,0) [-1|1] "mm" PLC
 SG_ Status : 48|16@1+ (1,0) [0|0] "" PLC
BO_ 769 Life: 2 VOLCOMP
 SG_ Heartbeat : 0|8@1+ (1,0) [0|0] "" PLC
)";

TEST(CanConfig, TakesLayoutsFromADbcFileRelativeToTheConfig) {
  TempDir dir;
  dir.write("machine.dbc", kMachineDbc);
  const std::string file = dir.write("daemon.json", "{}");
  json c = baseConfig();
  c["dbc"] = "machine.dbc";
  c["inputs"] = {
      {"position",
       {{"X", {{"dbc", "X_Pos"}}}, {"Y", {{"dbc", "Positions.Y_Pos"}}}, {"Z", {{"dbc", "Z_Pos"}}}}},
      {"enable", {{"dbc", "Enable"}}},
      {"homed", {{"dbc", "Homed"}}}};
  // Two input frames without sequence counters: only the sync trigger accepts that.
  c["trigger"] = "sync";
  c["sync"] = {{"id", "0x80"}};
  c["outputs"] = {
      {"offset", {{"X", {{"dbc", "Off_X"}}}, {"Y", {{"dbc", "Off_Y"}}}, {"Z", {{"dbc", "Off_Z"}}}}},
      {"status", {{"dbc", "Status"}}},
      {"heartbeat", {{"dbc", "Heartbeat"}}}};
  const CanLayout layout = loadCanLayout(c, file, "transport");
  ASSERT_EQ(layout.inputFrames.size(), 2u);
  EXPECT_EQ(layout.inputFrames[0].signals[0].spec.byteOrder, ByteOrder::Motorola);
  EXPECT_EQ(layout.inputFrames[0].signals[0].spec.name, "X_Pos");
  ASSERT_EQ(layout.outputFrames.size(), 2u);
  EXPECT_EQ(layout.outputFrames[1].length, 2u);  // the DBC message length, not just 1 byte
  EXPECT_FALSE(layout.hasSequence);

  c["inputs"]["homed"] = {{"dbc", "Mux"}};
  expectErrorIn(c, file, "transport.inputs.homed.dbc", "multiplexed");
  c["inputs"]["homed"] = {{"dbc", "Missing"}};
  expectErrorIn(c, file, "transport.inputs.homed.dbc", "no signal Missing");
  c.erase("dbc");
  c["inputs"]["homed"] = {{"dbc", "Homed"}};
  expectErrorIn(c, file, "transport.inputs.position.X.dbc", "no \"dbc\" file");
}

}  // namespace
}  // namespace volcomp::can

namespace volcomp::can {
namespace {

// The example of docs/can.md (tests/can/data): a DBC and the transport section using it.
TEST(CanConfig, DocumentedExampleLoads) {
  const std::string file = std::string(VOLCOMP_CAN_TEST_DATA) + "/can-transport.json";
  std::ifstream in(file);
  ASSERT_TRUE(in) << file;
  const nlohmann::json document = nlohmann::json::parse(in);
  const CanLayout layout = loadCanLayout(document.at("transport"), file, "transport");
  EXPECT_EQ(layout.interfaceName, "can0");
  EXPECT_TRUE(layout.hasSequence);
  EXPECT_TRUE(layout.hasAppliedOffsets);
  ASSERT_EQ(layout.inputFrames.size(), 3u);
  ASSERT_EQ(layout.outputFrames.size(), 2u);
  EXPECT_EQ(layout.outputFrames[0].id, 768u);
  EXPECT_EQ(layout.outputFrames[0].length, 8u);
  EXPECT_EQ(layout.outputFrames[1].length, 1u);
  EXPECT_EQ(layout.staleTimeout, std::chrono::milliseconds(100));
}

}  // namespace
}  // namespace volcomp::can
