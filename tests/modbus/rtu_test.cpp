#include <gtest/gtest.h>

#include "loopback_fixture.hpp"
#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/error.hpp"

namespace volcomp::test {
namespace {

constexpr sim::Vec3 kAt{10.5, 250.0001, -12.0};

TEST(ModbusRtuPty, ReadsAndWritesOverAPseudoTerminal) {
  auto lb = Loopback::rtu(kAt);
  ASSERT_FALSE(lb->server->devicePath().empty());
  ASSERT_FALSE(lb->port->connect()) << lb->server->devicePath();
  loop::AxisSample s;
  ASSERT_FALSE(lb->port->read(s));
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(s.positionMm[k], kAt[k], 1e-9);
  EXPECT_TRUE(s.enable);
  loop::OffsetCommand c;
  c.offsetMm = {0.0042, -0.0017, 0.0};
  c.heartbeat = 3;
  ASSERT_FALSE(lb->port->write(c));
  const auto writes = lb->machine.writes();
  ASSERT_EQ(writes.size(), 1U);
  EXPECT_NEAR(writes[0].offsetMm[0], 0.0042, 1e-9);
  EXPECT_EQ(writes[0].heartbeat, 3);
}

TEST(ModbusRtuPty, ExceptionAndSilenceThenReopen) {
  auto lb = Loopback::rtu(kAt);
  ASSERT_FALSE(lb->port->connect());
  loop::AxisSample s;
  lb->machine.exception(lb->now(), 6, 0.0);
  EXPECT_EQ(lb->port->read(s), modbus::Errc::server_device_busy);
  lb->machine.resume();
  // RTU has no connection: a silent slave is a timeout, then link loss after two of them.
  lb->machine.stall(lb->now(), 0.0);
  EXPECT_EQ(lb->port->read(s), modbus::Errc::response_timeout);
  const std::error_code ec = lb->port->read(s);
  EXPECT_TRUE(loop::isLinkError(ec)) << ec.message();
  EXPECT_FALSE(lb->port->connected());
  // The device can be opened again (no exclusive lock left behind) and the slave answers.
  lb->machine.resume();
  ASSERT_FALSE(lb->port->connect());
  ASSERT_FALSE(lb->port->read(s));
  EXPECT_NEAR(s.positionMm[1], kAt[1], 1e-9);
}

}  // namespace
}  // namespace volcomp::test
