// What the daemon's CAN port makes of each datagram a raw socket could return, without a CAN
// interface (CanControllerPort::receive, the path every received frame takes): a complete set is
// assembled from well-formed frames, and every malformed, foreign, remote or error frame is
// counted and changes nothing else. The same path is fuzzed (fuzz/can_frames_fuzzer.cpp).

#include <cstdint>
#include <cstring>
#include <string>
#include <variant>

#include <gtest/gtest.h>
#include <linux/can/error.h>

#include "volcomp/can/controller_port.hpp"
#include "volcomp/can/signal.hpp"
#include "volcomp/config/daemon_config.hpp"

namespace volcomp::can {
namespace {

CanLayout exampleLayout() {
  return std::get<CanLayout>(
      config::loadDaemonConfig(VOLCOMP_EXAMPLES_DIR + "/volcompd-can.json").transport);
}

/// A classical frame of `id` whose payload is `bits`, little-endian (the example DBC is Intel).
canfd_frame classical(canid_t id, std::uint64_t bits, std::uint8_t len = 8) {
  canfd_frame f{};
  f.can_id = id;
  f.len = len;
  std::memcpy(f.data, &bits, sizeof bits);
  return f;
}

/// The example's three input frames for one PLC cycle `seq` (positions X 1.2345 mm, Y -2 mm,
/// Z -3 mm, enabled and homed, no applied offsets).
void sendSet(CanControllerPort& port, std::uint64_t seq) {
  const std::uint64_t x = 12345, y = (std::uint64_t{1} << 28) - 20000;  // 28-bit two's complement
  port.receive(classical(256, x | (y << 28) | (seq << 56)), CAN_MTU);
  const std::uint64_t z = static_cast<std::uint32_t>(-30000);
  port.receive(classical(257, z | (std::uint64_t{3} << 32) | (seq << 56)), CAN_MTU);
  port.receive(classical(258, seq << 56), CAN_MTU);
}

TEST(CanReceive, WellFormedFramesMakeACompleteSet) {
  CanControllerPort port(exampleLayout());
  sendSet(port, 7);
  EXPECT_EQ(port.stats().framesReceived, 3u);
  EXPECT_EQ(port.stats().completeSets, 1u);
  ASSERT_EQ(port.lastInputFrames().size(), 3u);
  double x = 0.0;
  const SignalSpec& xSpec = port.layout().inputFrames[0].signals[0].spec;
  ASSERT_FALSE(decode(xSpec, payloadOf(port.lastInputFrames()[0]), x));
  EXPECT_NEAR(x, 1.2345, 1e-12);
}

TEST(CanReceive, HostileDatagramsAreCountedAndChangeNothing) {
  CanControllerPort port(exampleLayout());
  sendSet(port, 1);
  const auto frames = port.lastInputFrames();
  canfd_frame oversized = classical(256, 0);
  oversized.len = 64;  // a classical frame claiming an FD length
  port.receive(oversized, CAN_MTU);
  port.receive(classical(256, 0), CANFD_MTU);  // an FD datagram on a classical link
  port.receive(classical(256, 0), 3);          // a size no CAN socket returns
  port.receive(classical(256 | CAN_RTR_FLAG, 0, 0), CAN_MTU);
  port.receive(classical(257, 0, 4), CAN_MTU);  // shorter than its signals need
  EXPECT_EQ(port.stats().malformedFrames, 5u);
  port.receive(classical(256 | CAN_EFF_FLAG, 0), CAN_MTU);  // the right id in the other format
  port.receive(classical(0x7FF, 0), CAN_MTU);
  EXPECT_EQ(port.stats().unknownFrames, 2u);
  EXPECT_EQ(port.lastInputFrames(), frames);
  EXPECT_EQ(port.stats().completeSets, 1u);

  canfd_frame passive = classical(CAN_ERR_FLAG | CAN_ERR_CRTL, 0);
  passive.data[1] = CAN_ERR_CRTL_RX_PASSIVE;
  port.receive(passive, CAN_MTU);
  EXPECT_EQ(port.busState(), BusState::ErrorPassive);
  port.receive(classical(CAN_ERR_FLAG | CAN_ERR_BUSOFF, 0), CAN_MTU);
  EXPECT_EQ(port.busState(), BusState::BusOff);
  port.receive(classical(CAN_ERR_FLAG | CAN_ERR_RESTARTED, 0), CAN_MTU);
  EXPECT_EQ(port.busState(), BusState::ErrorActive);
  EXPECT_EQ(port.stats().errorFrames, 3u);

  // The peer behaves again: the next cycle is a complete set.
  sendSet(port, 2);
  EXPECT_EQ(port.stats().completeSets, 2u);
}

}  // namespace
}  // namespace volcomp::can
