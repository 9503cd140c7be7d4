// Interoperability with can-utils, an implementation independent of ours: frames the driver
// writes are decoded by `candump`, frames injected with `cansend` are understood by the driver.
// The layout comes from a DBC with 29-bit identifiers and Motorola (big-endian) signals.
#include "volcomp/can/controller_port.hpp"
#include "volcomp/config/can_config.hpp"

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>

#include "temp_files.hpp"
#include "vcan_util.hpp"
#include "wait_until.hpp"

namespace volcomp::can {
namespace {

using namespace std::chrono_literals;

// 0x80000000 + id marks a 29-bit identifier: 2147483904 = 0x100, 2147483905 = 0x101,
// 2147484416 = 0x300, 2147484417 = 0x301.
constexpr const char* kDbc = R"(VERSION ""
BU_: PLC VOLCOMP
BO_ 2147483904 PosXY: 8 PLC
 SG_ X : 7|24@0- (0.0001,0) [-800|800] "mm" VOLCOMP
 SG_ Y : 31|24@0- (0.0001,0) [-800|800] "mm" VOLCOMP
 SG_ Seq1 : 63|8@0+ (1,0) [0|255] "" VOLCOMP
BO_ 2147483905 PosZ: 8 PLC
 SG_ Z : 7|32@0- (0.0001,0) [0|0] "mm" VOLCOMP
 SG_ Enable : 39|1@0+ (1,0) [0|1] "" VOLCOMP
 SG_ Homed : 38|1@0+ (1,0) [0|1] "" VOLCOMP
 SG_ Seq2 : 63|8@0+ (1,0) [0|255] "" VOLCOMP
BO_ 2147484416 Out: 8 VOLCOMP
 SG_ OffX : 7|16@0- (0.001,0) [-30|30] "mm" PLC
 SG_ OffY : 23|16@0- (0.001,0) [-30|30] "mm" PLC
 SG_ OffZ : 39|16@0- (0.001,0) [-30|30] "mm" PLC
 SG_ Status : 55|16@0+ (1,0) [0|65535] "" PLC
BO_ 2147484417 Life: 1 VOLCOMP
 SG_ Heartbeat : 7|8@0+ (1,0) [0|255] "" PLC
)";

class CanUtilsInterop : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_.write("machine.dbc", kDbc);
    const nlohmann::json config{
        {"interface", test::interfaceName()},
        {"trigger", "broadcast"},
        {"dbc", "machine.dbc"},
        {"timeouts", {{"stale_ms", 2000}}},
        {"inputs",
         {{"position", {{"X", {{"dbc", "X"}}}, {"Y", {{"dbc", "Y"}}}, {"Z", {{"dbc", "Z"}}}}},
          {"enable", {{"dbc", "Enable"}}},
          {"homed", {{"dbc", "Homed"}}},
          {"sequence", nlohmann::json::array({{{"dbc", "Seq1"}}, {{"dbc", "Seq2"}}})}}},
        {"outputs",
         {{"offset",
           {{"X", {{"dbc", "OffX"}}}, {"Y", {{"dbc", "OffY"}}}, {"Z", {{"dbc", "OffZ"}}}}},
          {"status", {{"dbc", "Status"}}},
          {"heartbeat", {{"dbc", "Heartbeat"}}}}}};
    port_ = std::make_unique<CanControllerPort>(
        config::loadCanLayout(config, (dir_.path() / "daemon.json").string(), "transport"));
    ASSERT_FALSE(port_->connect());
  }
  volcomp::testing::TempDir dir_;
  std::unique_ptr<CanControllerPort> port_;
};

TEST_F(CanUtilsInterop, CansendFramesAreUnderstood) {
  // Derived by hand (big-endian signals): X = 123.4567 mm = raw 0x12D687 -> 12 D6 87;
  // Y = -0.0001 mm = raw -1 -> FF FF FF; sequence 5 in byte 7.
  // Z = -250 mm = raw -2500000 = 0xFFD9DA60 -> FF D9 DA 60; enable = byte 4 bit 7, homed = byte 4
  // bit 6 -> C0; sequence 5. Eight-digit identifiers make cansend send 29-bit frames.
  const std::string iface = test::interfaceName();
  ASSERT_EQ(test::run("cansend " + iface + " 00000100#12D687FFFFFF0005"), 0);
  ASSERT_EQ(test::run("cansend " + iface + " 00000101#FFD9DA60C0000005"), 0);
  loop::AxisSample sample;
  ASSERT_FALSE(port_->read(sample));
  EXPECT_NEAR(sample.positionMm[0], 123.4567, 1e-9);
  EXPECT_NEAR(sample.positionMm[1], -0.0001, 1e-12);
  EXPECT_NEAR(sample.positionMm[2], -250.0, 1e-9);
  EXPECT_TRUE(sample.enable);
  EXPECT_TRUE(sample.homed);
  EXPECT_EQ(sample.sequence, 5);

  // The same identifiers as 11-bit frames are other frames: not inputs (the kernel filter drops
  // them). A following 29-bit set (sequence 7, enable and homed off) is the next set received.
  ASSERT_EQ(test::run("cansend " + iface + " 100#12D687FFFFFF0006"), 0);
  ASSERT_EQ(test::run("cansend " + iface + " 101#FFD9DA60C0000006"), 0);
  ASSERT_EQ(test::run("cansend " + iface + " 00000100#12D687FFFFFF0007"), 0);
  ASSERT_EQ(test::run("cansend " + iface + " 00000101#FFD9DA6000000007"), 0);
  ASSERT_TRUE(testutil::waitUntil([&] { return !port_->read(sample) && sample.sequence == 7; }));
  EXPECT_FALSE(sample.enable);
  EXPECT_FALSE(sample.homed);
  EXPECT_EQ(port_->stats().completeSets, 2u);
  EXPECT_EQ(port_->stats().framesReceived, 4u);
}

TEST_F(CanUtilsInterop, WrittenFramesAreDecodedByCandump) {
  test::OutputReader candump("candump -L " + test::interfaceName() +
                             ",00000300:1FFFFFFF,00000301:1FFFFFFF");
  ASSERT_TRUE(candump.ok());
  loop::OffsetCommand command;
  command.offsetMm = {0.012, -0.002, 0.25};
  command.status = 0x1009;
  command.heartbeat = 300;
  // candump may still be starting: write every cycle until it has printed both frames.
  std::map<std::string, std::string> seen;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        EXPECT_FALSE(port_->write(command));
        while (auto line = candump.line(20ms)) {
          // "(1700000000.123456) vcan0 00000300#000CFFFE00FA1009"
          const std::size_t hash = line->find('#');
          const std::size_t space = line->rfind(' ', hash);
          if (hash == std::string::npos || space == std::string::npos) continue;
          seen[line->substr(space + 1, hash - space - 1)] = line->substr(hash + 1);
        }
        return seen.size() == 2;
      },
      10s));
  // Big-endian: X 12 µm = 00 0C, Y -2 µm = FF FE, Z 250 µm = 00 FA, status 0x1009 = 10 09;
  // the heartbeat 300 wraps to 44 = 0x2C in its 8 bits.
  EXPECT_EQ(seen["00000300"], "000CFFFE00FA1009");
  EXPECT_EQ(seen["00000301"], "2C");
}

}  // namespace
}  // namespace volcomp::can
