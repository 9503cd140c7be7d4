#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "loopback_fixture.hpp"
#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/error.hpp"
#include "wait_until.hpp"

namespace volcomp::test {
namespace {

using loop::AxisSample;
using loop::isLinkError;
using loop::OffsetCommand;
using modbus::Errc;

constexpr sim::Vec3 kAt{123.4567, -45.5, -300.25};

TEST(ModbusTcpLoopback, ReadsPositionsFlagsCounterAndAppliedOffsets) {
  sim::MachineOptions opt;
  opt.initialOffsetMm = {0.0123, -0.0045, 0.0};
  auto lb = Loopback::tcp(kAt, opt);
  ASSERT_FALSE(lb->port->connect());
  ASSERT_TRUE(lb->port->connected());
  AxisSample s;
  ASSERT_FALSE(lb->port->read(s));
  // Positions travel as int32 counts of 0.1 um: exact to 1e-4 mm (plus double rounding).
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(s.positionMm[k], kAt[k], 1e-9);
  EXPECT_TRUE(s.enable);
  EXPECT_TRUE(s.homed);
  ASSERT_TRUE(s.hasAppliedOffsets);
  EXPECT_NEAR(s.appliedOffsetMm[0], 0.0123, 1e-9);
  EXPECT_NEAR(s.appliedOffsetMm[1], -0.0045, 1e-9);
  ASSERT_TRUE(s.hasSequence);
  const auto first = s.sequence;
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_NE(s.sequence, first) << "the controller's life counter moves between reads";
  // One FC03 per read: inputs are contiguous holding registers.
  EXPECT_EQ(lb->port->statistics().transactions, 2U);

  lb->machine.setEnable(false);
  lb->machine.setHomed(false);
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_FALSE(s.enable);
  EXPECT_FALSE(s.homed);
}

TEST(ModbusTcpLoopback, WritesOffsetsStatusAndHeartbeatInOneTransaction) {
  auto lb = Loopback::tcp(kAt);
  ASSERT_FALSE(lb->port->connect());
  OffsetCommand c;
  c.offsetMm = {0.012, -0.0031, 0.0005};
  c.status = 0x0005;
  c.heartbeat = 7;
  ASSERT_FALSE(lb->port->write(c));
  EXPECT_EQ(lb->port->statistics().transactions, 1U);
  // The server hands the write to the machine before it replies: no waiting needed.
  const auto writes = lb->machine.writes();
  ASSERT_EQ(writes.size(), 1U);
  EXPECT_FALSE(writes[0].partial);
  EXPECT_NEAR(writes[0].offsetMm[0], 0.012, 1e-9);
  EXPECT_NEAR(writes[0].offsetMm[1], -0.0031, 1e-9);
  EXPECT_NEAR(writes[0].offsetMm[2], 0.0005, 1e-9);
  EXPECT_EQ(writes[0].status, 5);
  EXPECT_EQ(writes[0].heartbeat, 7);
  AxisSample s;
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_NEAR(s.appliedOffsetMm[0], 0.012, 1e-9);
  // `commanded` semantics: the position register does not include the offset.
  EXPECT_NEAR(s.positionMm[0], kAt[0], 1e-9);
}

TEST(ModbusTcpLoopback, ActualSemanticsIncludeTheAppliedOffset) {
  sim::MachineOptions opt;
  opt.semantics = loop::PositionSemantics::Actual;
  auto lb = Loopback::tcp(kAt, opt);
  ASSERT_FALSE(lb->port->connect());
  OffsetCommand c;
  c.offsetMm = {0.02, -0.01, 0.003};
  ASSERT_FALSE(lb->port->write(c));
  AxisSample s;
  ASSERT_FALSE(lb->port->read(s));
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(s.positionMm[k], kAt[k] + c.offsetMm[k], 1e-9);
}

TEST(ModbusTcpLoopback, Fc23WritesAndReadsInOneTransaction) {
  auto lb = Loopback::tcp(kAt, {}, /*fc23=*/true);
  ASSERT_FALSE(lb->port->connect());
  AxisSample s;
  ASSERT_FALSE(lb->port->read(s));  // first cycle: a plain FC03
  OffsetCommand c;
  c.offsetMm = {-0.004, 0.0, 0.0071};
  c.heartbeat = 1;
  ASSERT_FALSE(lb->port->write(c));  // FC23
  ASSERT_FALSE(lb->port->read(s));   // served from the FC23 read half
  EXPECT_EQ(lb->port->statistics().transactions, 2U);
  EXPECT_NEAR(s.positionMm[2], kAt[2], 1e-9);
  // The server executes the write before the read: the read-back already shows it.
  EXPECT_NEAR(s.appliedOffsetMm[2], 0.0071, 1e-9);
  ASSERT_EQ(lb->machine.writes().size(), 1U);
  // Without a preceding FC23 the next read is a transaction again.
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_EQ(lb->port->statistics().transactions, 3U);
}

TEST(ModbusTcpLoopback, ExceptionRepliesAreModbusErrorsOnALiveLink) {
  auto lb = Loopback::tcp(kAt);
  ASSERT_FALSE(lb->port->connect());
  lb->machine.exception(lb->now(), 4, 0.0);
  AxisSample s;
  const std::error_code ec = lb->port->read(s);
  EXPECT_EQ(ec, Errc::server_device_failure);
  EXPECT_EQ(ec.category(), modbus::modbusCategory());
  EXPECT_FALSE(isLinkError(ec));
  EXPECT_TRUE(lb->port->connected());
  lb->machine.exception(lb->now(), 2, 0.0);
  EXPECT_EQ(lb->port->write(OffsetCommand{}), Errc::illegal_data_address);
  EXPECT_TRUE(lb->machine.writes().empty()) << "a refused write is not applied";
  lb->machine.resume();
  EXPECT_FALSE(lb->port->read(s));
  EXPECT_EQ(lb->port->statistics().exceptions, 2U);
}

TEST(ModbusTcpLoopback, StallTimesOutThenCountsAsLinkLoss) {
  auto lb = Loopback::tcp(kAt);  // 100 ms timeout, 2 timeouts = link lost
  ASSERT_FALSE(lb->port->connect());
  lb->machine.stall(lb->now(), 0.0);
  AxisSample s;
  std::error_code ec = lb->port->read(s);
  EXPECT_EQ(ec, Errc::response_timeout);
  EXPECT_EQ(ec, std::errc::timed_out) << "a response timeout compares equal to errc::timed_out";
  EXPECT_FALSE(isLinkError(ec));
  EXPECT_TRUE(lb->port->connected());
  ec = lb->port->read(s);
  EXPECT_EQ(ec, std::errc::not_connected);
  EXPECT_TRUE(isLinkError(ec));
  EXPECT_FALSE(lb->port->connected());
  EXPECT_EQ(lb->port->read(s), std::errc::not_connected);
  // The server answers again: reconnecting works and the stale replies are gone.
  lb->machine.resume();
  ASSERT_FALSE(lb->port->connect());
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_NEAR(s.positionMm[1], kAt[1], 1e-9);
}

TEST(ModbusTcpLoopback, DroppedLinkIsALinkErrorAndReconnectWorks) {
  auto lb = Loopback::tcp(kAt);
  ASSERT_FALSE(lb->port->connect());
  AxisSample s;
  ASSERT_FALSE(lb->port->read(s));
  lb->machine.dropLink(lb->now(), 0.0);
  // Until the server has closed the socket a request may just go unanswered (a timeout); then
  // the next one sees the closed connection.
  std::error_code ec;
  ASSERT_TRUE(testutil::waitUntil([&] {
    ec = lb->port->read(s);
    return isLinkError(ec);
  })) << ec.message();
  EXPECT_FALSE(lb->port->connected());
  // While the link is down the port does not listen: connecting is refused.
  ec = lb->port->connect();
  EXPECT_EQ(ec, std::errc::connection_refused);
  EXPECT_TRUE(isLinkError(ec));
  lb->machine.resume();
  ASSERT_TRUE(testutil::waitUntil([&] { return !lb->port->connect(); }));
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_NEAR(s.positionMm[0], kAt[0], 1e-9);
  OffsetCommand c;
  c.offsetMm = {0.001, 0.002, 0.003};
  ASSERT_FALSE(lb->port->write(c));
  EXPECT_EQ(lb->machine.writes().size(), 1U);
}

TEST(ModbusTcpLoopback, ConnectToAClosedPortIsRefused) {
  // Take a free port from a server, then stop it: nothing listens there any more.
  auto lb = Loopback::tcp(kAt);
  lb->server->stop();
  const std::error_code ec = lb->port->connect();
  EXPECT_EQ(ec, std::errc::connection_refused);
  EXPECT_TRUE(isLinkError(ec));
  EXPECT_FALSE(lb->port->connected());
}

TEST(ModbusTcpLoopback, UnencodableOutputsAreNotSent) {
  auto lb = Loopback::tcp(kAt);
  ASSERT_FALSE(lb->port->connect());
  OffsetCommand c;
  c.offsetMm = {0.0, std::numeric_limits<double>::quiet_NaN(), 0.0};
  EXPECT_EQ(lb->port->write(c), Errc::value_not_finite);
  // int32 at 10000 counts/mm holds +-214748 mm; 1e6 mm does not fit.
  c.offsetMm = {1e6, 0.0, 0.0};
  EXPECT_EQ(lb->port->write(c), Errc::value_out_of_range);
  EXPECT_EQ(lb->port->statistics().transactions, 0U);
  EXPECT_TRUE(lb->machine.writes().empty());
  EXPECT_TRUE(lb->port->connected());
}

TEST(ModbusTcpLoopback, NotConnectedBeforeConnect) {
  auto lb = Loopback::tcp(kAt);
  AxisSample s;
  EXPECT_EQ(lb->port->read(s), std::errc::not_connected);
  EXPECT_EQ(lb->port->write(OffsetCommand{}), std::errc::not_connected);
}

TEST(ModbusTcpLoopback, PortFromTheParsedTransportSection) {
  auto lb = Loopback::tcp(kAt);
  auto port = std::make_unique<modbus::ModbusControllerPort>(config::parseModbusSettings(
      tcpTransportJson(lb->server->port()), "daemon.json", "transport"));
  ASSERT_FALSE(port->connect());
  AxisSample s;
  ASSERT_FALSE(port->read(s));
  EXPECT_NEAR(s.positionMm[2], kAt[2], 1e-9);
  nlohmann::json bad = tcpTransportJson(1);
  bad["registers"]["heartbeat"] = 99;
  EXPECT_THROW(config::parseModbusSettings(bad, "daemon.json", "transport"), config::ConfigError);
}

}  // namespace
}  // namespace volcomp::test
