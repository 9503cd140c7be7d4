// The SocketCAN driver on a real (virtual) CAN interface, against a peer socket written with
// plain SocketCAN calls. Needs a kernel with vcan (run by run_vcan_tests.sh, in QEMU if need be).
#include "volcomp/can/controller_port.hpp"
#include "volcomp/config/can_config.hpp"

#include <linux/can/error.h>

#include <atomic>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <asio/executor_work_guard.hpp>
#include <asio/post.hpp>

#include "vcan_layout.hpp"
#include "vcan_util.hpp"
#include "volcomp/can/controller_node.hpp"
#include "volcomp/can/errors.hpp"
#include "wait_until.hpp"

namespace volcomp::can {
namespace {

using namespace std::chrono_literals;
using test::PeerSocket;

// The input set of testConfig() with sequence 5, derived by hand:
// X = 123.4567 mm -> raw 1234567 = 0x12D687 -> little-endian 87 D6 12 (bytes 0..2);
// Y = -0.0001 mm -> raw -1 -> 24 bits FF FF FF (bytes 3..5); sequence 5 in byte 7.
// Z = -250 mm -> raw -2500000 = 0xFFD9DA60 -> 60 DA D9 FF; enable and homed = bits 0, 1 of
// byte 4 -> 03; sequence 5 in byte 7.
const std::vector<std::uint8_t> kFrame100{0x87, 0xD6, 0x12, 0xFF, 0xFF, 0xFF, 0x00, 0x05};
const std::vector<std::uint8_t> kFrame101{0x60, 0xDA, 0xD9, 0xFF, 0x03, 0x00, 0x00, 0x05};

std::vector<std::uint8_t> withSequence(std::vector<std::uint8_t> frame, std::uint8_t sequence) {
  frame[7] = sequence;
  return frame;
}

class VcanDriver : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(peer.ok()) << "no CAN interface " << test::interfaceName();
    ASSERT_TRUE(test::setInterfaceUp(test::interfaceName(), true));
  }
  void TearDown() override { test::setInterfaceUp(test::interfaceName(), true); }

  std::unique_ptr<CanControllerPort> makePort(const nlohmann::json& config) {
    auto port = std::make_unique<CanControllerPort>(
        config::loadCanLayout(config, "vcan-test.json", "transport"));
    EXPECT_FALSE(port->connect());
    return port;
  }
  void sendSet(std::uint8_t sequence) {
    ASSERT_TRUE(peer.send(0x100, withSequence(kFrame100, sequence)));
    ASSERT_TRUE(peer.send(0x101, withSequence(kFrame101, sequence)));
  }

  PeerSocket peer;
};

TEST_F(VcanDriver, ReadsACompleteBroadcastSetFromTheWire) {
  auto port = makePort(test::testConfig());
  sendSet(5);
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  EXPECT_NEAR(sample.positionMm[0], 123.4567, 1e-9);
  EXPECT_NEAR(sample.positionMm[1], -0.0001, 1e-12);
  EXPECT_NEAR(sample.positionMm[2], -250.0, 1e-9);
  EXPECT_TRUE(sample.enable);
  EXPECT_TRUE(sample.homed);
  EXPECT_TRUE(sample.hasSequence);
  EXPECT_EQ(sample.sequence, 5);
  EXPECT_FALSE(sample.hasAppliedOffsets);
  EXPECT_EQ(port->stats().completeSets, 1u);
  EXPECT_EQ(port->stats().framesReceived, 2u);
}

TEST_F(VcanDriver, WritesAllOutputFramesWithTheExpectedBytes) {
  auto port = makePort(test::testConfig());
  loop::OffsetCommand command;
  command.offsetMm = {0.012, -0.002, 0.25};
  command.status = 0x1009;
  command.heartbeat = 300;
  ASSERT_FALSE(port->write(command));
  // 0x300: X 12 µm = 0C 00, Y -2 µm = FE FF, Z 250 µm = FA 00, status 0x1009 = 09 10.
  const auto offsets = peer.receiveId(0x300, 2s);
  ASSERT_TRUE(offsets);
  EXPECT_EQ(offsets->len, 8);
  const std::vector<std::uint8_t> expected{0x0C, 0x00, 0xFE, 0xFF, 0xFA, 0x00, 0x09, 0x10};
  EXPECT_EQ(std::vector<std::uint8_t>(offsets->data, offsets->data + 8), expected);
  // 0x301: heartbeat 300 wraps to 300 - 256 = 44 = 0x2C in its 8-bit counter.
  const auto life = peer.receiveId(0x301, 2s);
  ASSERT_TRUE(life);
  EXPECT_EQ(life->len, 1);
  EXPECT_EQ(life->data[0], 0x2C);
  EXPECT_EQ(port->stats().framesSent, 2u);

  // An offset beyond int16 µm (32.768 mm) fails the whole write: nothing is sent.
  command.offsetMm[2] = 40.0;
  EXPECT_EQ(port->write(command), Errc::OutOfRange);
  EXPECT_FALSE(peer.receive(100ms).has_value());
}

TEST_F(VcanDriver, OnlyFramesWithTheSameSequenceFormASet) {
  auto port = makePort(test::testConfig());
  ASSERT_TRUE(peer.send(0x100, withSequence(kFrame100, 5)));
  ASSERT_TRUE(peer.send(0x101, withSequence(kFrame101, 6)));
  loop::AxisSample sample;
  EXPECT_EQ(port->read(sample), Errc::StaleInput);  // waits the stale timeout for a first set
  EXPECT_EQ(port->stats().completeSets, 0u);
  EXPECT_GE(port->stats().discardedFrames, 1u);
  ASSERT_TRUE(peer.send(0x100, withSequence(kFrame100, 6)));
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(sample.sequence, 6);
  EXPECT_EQ(port->stats().completeSets, 1u);
}

TEST_F(VcanDriver, StaleSetsAreRefused) {
  auto port = makePort(test::testConfig("broadcast", 50.0));
  loop::AxisSample sample;
  // Like a controller, keep sending until the driver has a set (a loaded machine may take longer
  // than the 50 ms stale timeout between one send and the next read).
  auto sendUntilRead = [&](std::uint8_t sequence) {
    return testutil::waitUntil([&] {
      peer.send(0x100, withSequence(kFrame100, sequence));
      peer.send(0x101, withSequence(kFrame101, sequence));
      return !port->read(sample) && sample.sequence == sequence;
    });
  };
  ASSERT_TRUE(sendUntilRead(1));
  // No new frames: once the set is older than 50 ms, read reports stale input.
  EXPECT_TRUE(testutil::waitUntil([&] { return port->read(sample) == Errc::StaleInput; }));
  EXPECT_TRUE(sendUntilRead(2));
}

TEST_F(VcanDriver, MalformedAndShortFramesAreIgnoredAndCounted) {
  auto port = makePort(test::testConfig());
  ASSERT_TRUE(peer.send(0x100, {0x01, 0x02}));       // 2 bytes, the layout needs 8
  ASSERT_TRUE(peer.send(0x101, {}));                 // empty
  ASSERT_TRUE(peer.send(0x101 | CAN_RTR_FLAG, {}));  // remote request: filtered by the kernel
  ASSERT_TRUE(peer.send(0x555, {1, 2, 3}));          // not an input: filtered by the kernel
  ASSERT_TRUE(testutil::waitUntil([&] {
    loop::AxisSample ignored;
    port->read(ignored);
    return port->stats().malformedFrames == 2;
  }));
  EXPECT_EQ(port->stats().completeSets, 0u);
  sendSet(7);
  loop::AxisSample sample;
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(sample.sequence, 7);
  EXPECT_NEAR(sample.positionMm[0], 123.4567, 1e-9);
  EXPECT_EQ(port->stats().malformedFrames, 2u);
}

TEST_F(VcanDriver, BusOffErrorFrameIsAFaultUntilRestart) {
  auto port = makePort(test::testConfig());
  sendSet(1);
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_BUSOFF, std::vector<std::uint8_t>(8, 0)));
  ASSERT_TRUE(testutil::waitUntil([&] { return port->read(sample) == Errc::BusOff; }));
  EXPECT_FALSE(loop::isLinkError(Errc::BusOff));
  EXPECT_EQ(port->busState(), BusState::BusOff);
  EXPECT_EQ(port->write(loop::OffsetCommand{}), Errc::BusOff);
  EXPECT_EQ(port->stats().busOffEvents, 1u);
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_RESTARTED, std::vector<std::uint8_t>(8, 0)));
  sendSet(2);
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(port->busState(), BusState::ErrorActive);
  EXPECT_EQ(sample.sequence, 2);
}

// A restart report lost (a flooded receive queue drops it): the interface's carrier, which the
// kernel's CAN drivers take down at bus-off and raise at the restart, ends bus-off once no
// bus-off report has come for the stale timeout. vcan always has its carrier.
TEST_F(VcanDriver, BusOffWithoutARestartReportEndsWithTheCarrierAfterTheStaleTimeout) {
  auto port = makePort(test::testConfig("broadcast", 200.0));
  const auto staleTimeout = port->layout().staleTimeout;
  sendSet(1);
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  const auto reported = std::chrono::steady_clock::now();
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_BUSOFF, std::vector<std::uint8_t>(8, 0)));
  ASSERT_TRUE(testutil::waitUntil([&] { return port->read(sample) == Errc::BusOff; }));
  EXPECT_EQ(port->write(loop::OffsetCommand{}), Errc::BusOff);
  ASSERT_TRUE(testutil::waitUntil(
      [&] { return port->write(loop::OffsetCommand{}) != Errc::BusOff; },
      std::chrono::duration_cast<std::chrono::milliseconds>(10 * staleTimeout)));
  EXPECT_GE(std::chrono::steady_clock::now() - reported, staleTimeout);
  EXPECT_EQ(port->busState(), BusState::ErrorActive);
  EXPECT_EQ(port->stats().busOffEndedByCarrier, 1u);
  sendSet(2);
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(sample.sequence, 2);
}

TEST_F(VcanDriver, ErrorPassiveIsAFaultButOffsetsCanStillBeWritten) {
  auto port = makePort(test::testConfig());
  std::vector<std::uint8_t> details(8, 0);
  details[1] = CAN_ERR_CRTL_TX_PASSIVE;
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, details));
  loop::AxisSample sample;
  ASSERT_TRUE(testutil::waitUntil([&] { return port->read(sample) == Errc::ErrorPassive; }));
  EXPECT_EQ(port->stats().errorPassiveEvents, 1u);
  // The daemon ramps the offsets to zero in fault: writing must still work.
  EXPECT_FALSE(port->write(loop::OffsetCommand{}));
  details[1] = CAN_ERR_CRTL_ACTIVE;
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, details));
  sendSet(3);
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(port->busState(), BusState::ErrorActive);
}

// The kernel reports the way back from error-passive once; a flooded receive queue can drop that
// report. Frames dropped after the passive report, and complete input sets arriving after it for
// the stale timeout with no new report, end the state.
TEST_F(VcanDriver, ErrorPassiveWhoseEndWasDroppedEndsOnceCompleteSetsArriveAgain) {
  auto port = makePort(test::testConfig("broadcast", 200.0));
  const auto staleTimeout = port->layout().staleTimeout;
  std::vector<std::uint8_t> details(8, 0);
  details[1] = CAN_ERR_CRTL_TX_PASSIVE;
  const auto reported = std::chrono::steady_clock::now();
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, details));
  // Nothing drains the port's socket meanwhile: short frames on an input identifier (which its
  // filter lets through) fill the queue, and the error-active report behind them is dropped.
  for (int i = 0; i < 5000; ++i) peer.send(0x100, {0xFF, 0xFF});
  details[1] = CAN_ERR_CRTL_ACTIVE;
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, details));
  loop::AxisSample sample;
  EXPECT_EQ(port->read(sample), Errc::ErrorPassive);
  ASSERT_GT(port->stats().receiveQueueDrops, 0u);
  EXPECT_EQ(port->busState(), BusState::ErrorPassive) << "the error-active report got through";
  std::uint8_t sequence = 0;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        sendSet(++sequence);
        return !port->read(sample);
      },
      std::chrono::duration_cast<std::chrono::milliseconds>(10 * staleTimeout)));
  EXPECT_GE(std::chrono::steady_clock::now() - reported, staleTimeout);
  EXPECT_EQ(port->busState(), BusState::ErrorActive);
  EXPECT_EQ(port->stats().errorPassiveEndedAfterDrops, 1u);
  EXPECT_EQ(sample.sequence, sequence);
}

// Nothing dropped: no report can have been lost, and a controller that stays error-passive stays
// a fault however well its frames arrive.
TEST_F(VcanDriver, ErrorPassiveWithNothingDroppedStaysAFaultWhileFramesFlow) {
  auto port = makePort(test::testConfig("broadcast", 200.0));
  const auto staleTimeout = port->layout().staleTimeout;
  std::vector<std::uint8_t> details(8, 0);
  details[1] = CAN_ERR_CRTL_RX_PASSIVE;
  ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, details));
  loop::AxisSample sample;
  ASSERT_TRUE(testutil::waitUntil([&] { return port->read(sample) == Errc::ErrorPassive; }));
  std::uint8_t sequence = 0;
  EXPECT_FALSE(testutil::waitUntil(
      [&] {
        sendSet(++sequence);
        return port->read(sample) != Errc::ErrorPassive;
      },
      std::chrono::duration_cast<std::chrono::milliseconds>(3 * staleTimeout)));
  EXPECT_EQ(port->busState(), BusState::ErrorPassive);
  EXPECT_EQ(port->stats().receiveQueueDrops, 0u);
  EXPECT_EQ(port->stats().errorPassiveEndedAfterDrops, 0u);
  EXPECT_GT(port->stats().completeSets, 10u);
}

TEST_F(VcanDriver, InterfaceDownIsALinkErrorAndRecoveryWorks) {
  auto port = makePort(test::testConfig());
  sendSet(1);
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  ASSERT_TRUE(test::setInterfaceUp(test::interfaceName(), false));
  std::error_code ec;
  ASSERT_TRUE(testutil::waitUntil([&] {
    ec = port->read(sample);
    return loop::isLinkError(ec);
  }));
  EXPECT_EQ(ec, std::errc::network_down);
  EXPECT_FALSE(port->connected());
  EXPECT_EQ(port->write(loop::OffsetCommand{}), std::errc::not_connected);
  // While the interface is down, reconnecting fails as a link error (the loop backs off).
  EXPECT_EQ(port->connect(), std::errc::network_down);
  EXPECT_GE(port->stats().linkErrors, 1u);
  EXPECT_EQ(port->lastLinkError(), std::errc::network_down) << port->lastLinkError().message();

  ASSERT_TRUE(test::setInterfaceUp(test::interfaceName(), true));
  ASSERT_FALSE(port->connect());
  EXPECT_TRUE(port->connected());
  // The peer's socket saw the interface go down too: a controller would reopen it as well.
  PeerSocket freshPeer;
  ASSERT_TRUE(freshPeer.ok());
  ASSERT_TRUE(freshPeer.send(0x100, withSequence(kFrame100, 9)));
  ASSERT_TRUE(freshPeer.send(0x101, withSequence(kFrame101, 9)));
  ASSERT_TRUE(testutil::waitUntil([&] { return !port->read(sample); }));
  EXPECT_EQ(sample.sequence, 9);
  EXPECT_FALSE(port->write(loop::OffsetCommand{}));
}

TEST_F(VcanDriver, MissingInterfaceIsALinkError) {
  nlohmann::json c = test::testConfig();
  c["interface"] = "vcan-missing";
  auto port =
      std::make_unique<CanControllerPort>(config::loadCanLayout(c, "vcan-test.json", "transport"));
  EXPECT_EQ(port->connect(), std::errc::network_down);
  loop::AxisSample sample;
  EXPECT_EQ(port->read(sample), std::errc::not_connected);
}

/// The controller node on its own io_context and thread, as the simulator would run it.
class NodeThread {
 public:
  explicit NodeThread(const nlohmann::json& config)
      : node_(io_, config::loadCanLayout(config, "vcan-test.json", "transport")) {}
  ~NodeThread() { stop(); }
  std::error_code start() {
    const std::error_code ec = node_.open();
    if (!ec) thread_ = std::thread([this] { io_.run(); });
    return ec;
  }
  void stop() {
    work_.reset();
    asio::post(io_, [this] { node_.close(); });
    if (thread_.joinable()) thread_.join();
  }
  CanControllerNode& node() { return node_; }
  loop::OffsetCommand lastCommand() {
    std::lock_guard lock(mutex_);
    return last_;
  }
  std::uint64_t commands() const { return commands_; }
  void watchCommands() {
    node_.setCommandHandler([this](const loop::OffsetCommand& c) {
      std::lock_guard lock(mutex_);
      last_ = c;
      ++commands_;
    });
  }

 private:
  asio::io_context io_;
  asio::executor_work_guard<asio::io_context::executor_type> work_{io_.get_executor()};
  CanControllerNode node_;
  std::thread thread_;
  std::mutex mutex_;
  loop::OffsetCommand last_;
  std::atomic<std::uint64_t> commands_{0};
};

TEST_F(VcanDriver, SyncTriggerAsksTheNodeAndWaitsForItsAnswer) {
  NodeThread controller(test::testConfig("sync"));
  loop::AxisSample truth;
  truth.positionMm = {10.5, -20.25, 300.0};
  truth.enable = true;
  truth.homed = false;
  std::uint64_t sequence = 40;
  controller.node().setSyncHandler([&] { controller.node().publish(truth, sequence++); });
  controller.watchCommands();
  ASSERT_FALSE(controller.start());

  auto port = makePort(test::testConfig("sync"));
  for (int cycle = 0; cycle < 3; ++cycle) {
    loop::AxisSample sample;
    ASSERT_FALSE(port->read(sample)) << cycle;
    EXPECT_NEAR(sample.positionMm[0], 10.5, 1e-9);
    EXPECT_NEAR(sample.positionMm[1], -20.25, 1e-9);
    EXPECT_NEAR(sample.positionMm[2], 300.0, 1e-9);
    EXPECT_TRUE(sample.enable);
    EXPECT_FALSE(sample.homed);
    EXPECT_EQ(sample.sequence, 40 + cycle);
    loop::OffsetCommand command;
    command.offsetMm = {0.001 * cycle, -0.005, 0.1};
    command.status = static_cast<std::uint16_t>(cycle);
    command.heartbeat = static_cast<std::uint16_t>(cycle + 1);
    ASSERT_FALSE(port->write(command));
    ASSERT_TRUE(testutil::waitUntil(
        [&] { return controller.commands() == static_cast<std::uint64_t>(cycle + 1); }));
    const loop::OffsetCommand seen = controller.lastCommand();
    EXPECT_NEAR(seen.offsetMm[0], 0.001 * cycle, 1e-12);
    EXPECT_NEAR(seen.offsetMm[1], -0.005, 1e-12);
    EXPECT_NEAR(seen.offsetMm[2], 0.1, 1e-12);
    EXPECT_EQ(seen.status, cycle);
    EXPECT_EQ(seen.heartbeat, cycle + 1);
  }
  controller.stop();
  loop::AxisSample sample;
  EXPECT_EQ(port->read(sample), Errc::NoResponse);  // nobody answers the SYNC any more
}

TEST_F(VcanDriver, CanFdFramesBothWays) {
  nlohmann::json c = test::testConfig();
  c["fd"] = true;
  c["bitrate_switch"] = false;
  // Z moves to bytes 8..11 of 0x101, which makes it a 12-byte FD frame.
  c["inputs"]["position"]["Z"] = test::signal(0x101, 64, 32, "signed", 0.0001);
  auto port = makePort(c);
  std::vector<std::uint8_t> frame101(12, 0);
  frame101[4] = 0x03;  // enable, homed
  frame101[7] = 4;     // sequence
  // Z = 0.0002 mm -> raw 2 in bytes 8..11.
  frame101[8] = 0x02;
  ASSERT_TRUE(peer.sendFd(0x100, withSequence(kFrame100, 4)));
  ASSERT_TRUE(peer.sendFd(0x101, frame101));
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  EXPECT_NEAR(sample.positionMm[2], 0.0002, 1e-12);
  ASSERT_FALSE(port->write(loop::OffsetCommand{}));
  std::size_t mtu = 0;
  std::optional<canfd_frame> out;
  ASSERT_TRUE(testutil::waitUntil([&] {
    out = peer.receive(100ms, &mtu);
    return out && out->can_id == 0x300;
  }));
  EXPECT_EQ(mtu, static_cast<std::size_t>(CANFD_MTU));
  EXPECT_EQ(out->len, 8);
}

TEST_F(VcanDriver, ControllerNodeBroadcastRoundTrip) {
  // The node only sends here, so its io_context need not run.
  asio::io_context io;
  CanControllerNode node(io,
                         config::loadCanLayout(test::testConfig(), "vcan-test.json", "transport"));
  ASSERT_FALSE(node.open());
  auto port = makePort(test::testConfig());
  loop::AxisSample truth;
  truth.positionMm = {-1.2345, 0.0, 700.0001};
  truth.enable = false;
  truth.homed = true;
  ASSERT_FALSE(node.publish(truth, 258));  // the 8-bit counter carries 258 % 256 = 2
  loop::AxisSample sample;
  ASSERT_FALSE(port->read(sample));
  EXPECT_NEAR(sample.positionMm[0], -1.2345, 1e-9);
  EXPECT_NEAR(sample.positionMm[2], 700.0001, 1e-9);
  EXPECT_FALSE(sample.enable);
  EXPECT_TRUE(sample.homed);
  EXPECT_EQ(sample.sequence, 2);
  // Positions that do not fit their signals are refused before anything is sent.
  truth.positionMm[0] = 1000.0;  // int24 at 0.1 µm holds +-838.8608 mm
  EXPECT_EQ(node.publish(truth, 3), Errc::OutOfRange);
}

}  // namespace
}  // namespace volcomp::can
