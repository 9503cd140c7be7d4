// The server port in-process against libmodbus' own client (a peer we did not write): TCP on a
// port chosen at run time and RTU over a pseudo-terminal. Synchronised on conditions only.
#include "volcomp/modbus/server_port.hpp"

#include <fcntl.h>
#include <modbus/modbus.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <arpa/inet.h>

#include <atomic>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "test_maps.hpp"
#include "volcomp/config/modbus_config.hpp"
#include "volcomp/modbus/error.hpp"
#include "wait_until.hpp"

namespace volcomp::modbus {
namespace {

using nlohmann::json;
using testutil::waitUntil;

ModbusSettings serverSettings(const json& extra = json::object()) {
  return config::parseModbusSettings(test::serverTransportJson(extra), "test.json", "transport");
}

struct Client {
  explicit Client(std::uint16_t port) : ctx(modbus_new_tcp("127.0.0.1", port)) {
    modbus_set_response_timeout(ctx, 2, 0);
    connected = modbus_connect(ctx) == 0;
  }
  ~Client() {
    modbus_close(ctx);
    modbus_free(ctx);
  }
  modbus_t* ctx;
  bool connected = false;
};

/// Positions X, Y, Z (mm) as the example map's int32 ABCD registers, flags, life counter and
/// zero applied offsets: the whole input block 0..13.
std::array<std::uint16_t, 14> inputBlock(double x, double y, double z, std::uint16_t flags,
                                         std::uint16_t life) {
  std::array<std::uint16_t, 14> r{};
  const double mm[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    const auto counts = static_cast<std::int32_t>(std::lround(mm[k] * 10000.0));
    r[2 * k] = static_cast<std::uint16_t>(static_cast<std::uint32_t>(counts) >> 16);
    r[2 * k + 1] = static_cast<std::uint16_t>(static_cast<std::uint32_t>(counts) & 0xFFFF);
  }
  r[6] = flags;
  r[7] = life;
  return r;
}

double int32Mm(const std::uint16_t* r) {
  return static_cast<std::int32_t>((static_cast<std::uint32_t>(r[0]) << 16) | r[1]) / 10000.0;
}

TEST(ModbusServerPort, MasterWritesInputsAndReadsOutputs) {
  ModbusServerPort port(serverSettings());
  std::atomic<int> triggers{0};
  port.setCycleTrigger([&] { ++triggers; });
  ASSERT_FALSE(port.connect());
  ASSERT_NE(port.boundPort(), 0);
  Client master(port.boundPort());
  ASSERT_TRUE(master.connected);

  loop::AxisSample s;
  EXPECT_EQ(port.read(s), Errc::no_master_write);

  auto in = inputBlock(100.0, -250.5, 12.25, 3, 7);
  ASSERT_EQ(modbus_write_registers(master.ctx, 0, 14, in.data()), 14);
  ASSERT_TRUE(waitUntil([&] { return triggers == 1; }));
  ASSERT_FALSE(port.read(s));
  EXPECT_NEAR(s.positionMm[0], 100.0, 1e-9);
  EXPECT_NEAR(s.positionMm[1], -250.5, 1e-9);
  EXPECT_NEAR(s.positionMm[2], 12.25, 1e-9);
  EXPECT_TRUE(s.enable);
  EXPECT_TRUE(s.homed);
  EXPECT_TRUE(s.hasAppliedOffsets);
  EXPECT_TRUE(s.hasSequence);
  const std::uint16_t first = s.sequence;

  loop::OffsetCommand c;
  c.offsetMm = {0.0123, -0.0456, 0.0007};
  c.status = 1;
  c.heartbeat = 42;
  ASSERT_FALSE(port.write(c));
  std::array<std::uint16_t, 8> out{};
  ASSERT_EQ(modbus_read_registers(master.ctx, 14, 8, out.data()), 8);
  EXPECT_NEAR(int32Mm(&out[0]), 0.0123, 1e-9);
  EXPECT_NEAR(int32Mm(&out[2]), -0.0456, 1e-9);
  EXPECT_NEAR(int32Mm(&out[4]), 0.0007, 1e-9);
  EXPECT_EQ(out[6], 1);
  EXPECT_EQ(out[7], 42);

  // Positions in two writes complete one set; the life counter moved, so the set is fresh.
  in = inputBlock(101.0, -250.5, 12.25, 3, 8);
  ASSERT_EQ(modbus_write_registers(master.ctx, 0, 2, in.data()), 2);
  ASSERT_EQ(modbus_write_registers(master.ctx, 2, 12, in.data() + 2), 12);
  ASSERT_TRUE(waitUntil([&] { return port.counters().positionSets == 2; }));
  ASSERT_FALSE(port.read(s));
  EXPECT_NEAR(s.positionMm[0], 101.0, 1e-9);
  EXPECT_EQ(s.sequence, static_cast<std::uint16_t>(first + 1));
  // A set with a frozen life counter is not fresh: the loop's stale timeout runs on.
  ASSERT_EQ(modbus_write_registers(master.ctx, 0, 14, in.data()), 14);
  ASSERT_TRUE(waitUntil([&] { return port.counters().positionSets == 3; }));
  ASSERT_FALSE(port.read(s));
  EXPECT_EQ(s.sequence, static_cast<std::uint16_t>(first + 1));
}

TEST(ModbusServerPort, RefusesWritesOutsideTheInputBlockWithIllegalDataAddress) {
  ModbusServerPort port(serverSettings());
  ASSERT_FALSE(port.connect());
  Client master(port.boundPort());
  ASSERT_TRUE(master.connected);
  std::uint16_t v = 5;
  EXPECT_EQ(modbus_write_register(master.ctx, 14, v), -1);
  EXPECT_EQ(errno, EMBXILADD);
  std::array<std::uint16_t, 4> four{};
  EXPECT_EQ(modbus_write_registers(master.ctx, 12, 4, four.data()), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_read_registers(master.ctx, 20, 4, four.data()), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_read_input_registers(master.ctx, 0, 1, four.data()), -1);
  EXPECT_EQ(errno, EMBXILFUN);  // the bank has holding registers only
  EXPECT_EQ(port.counters().refused, 4U);
  // The connection stays usable, and nothing was written.
  ASSERT_EQ(modbus_read_registers(master.ctx, 14, 4, four.data()), 4);
  EXPECT_EQ(four[0], 0);
}

TEST(ModbusServerPort, LimitsConnections) {
  ModbusServerPort port(serverSettings());
  ASSERT_FALSE(port.connect());
  Client first(port.boundPort());
  ASSERT_TRUE(first.connected);
  std::array<std::uint16_t, 8> out{};
  ASSERT_EQ(modbus_read_registers(first.ctx, 14, 8, out.data()), 8);
  Client second(port.boundPort());  // TCP accepts it; the server closes it at once
  ASSERT_TRUE(waitUntil([&] { return port.counters().refusedConnections == 1; }));
  EXPECT_EQ(modbus_read_registers(second.ctx, 14, 8, out.data()), -1);
  ASSERT_EQ(modbus_read_registers(first.ctx, 14, 8, out.data()), 8);
  EXPECT_EQ(port.counters().connections, 1U);
}

TEST(ModbusServerPort, RefusesClientsNotAllowed) {
  ModbusServerPort port(serverSettings({{"allowed_clients", {"192.0.2.7"}}}));
  ASSERT_FALSE(port.connect());
  Client master(port.boundPort());
  std::array<std::uint16_t, 8> out{};
  ASSERT_TRUE(waitUntil([&] { return port.counters().refusedConnections == 1; }));
  EXPECT_EQ(modbus_read_registers(master.ctx, 14, 8, out.data()), -1);
  EXPECT_EQ(port.counters().connections, 0U);
}

TEST(ModbusServerPort, TimerTriggerDoesNotCallTheTrigger) {
  ModbusServerPort port(serverSettings({{"cycle_trigger", "timer"}}));
  std::atomic<int> triggers{0};
  port.setCycleTrigger([&] { ++triggers; });
  ASSERT_FALSE(port.connect());
  Client master(port.boundPort());
  auto in = inputBlock(1.0, 2.0, 3.0, 3, 1);
  ASSERT_EQ(modbus_write_registers(master.ctx, 0, 14, in.data()), 14);
  ASSERT_TRUE(waitUntil([&] { return port.counters().positionSets == 1; }));
  EXPECT_EQ(triggers, 0);
  loop::AxisSample s;
  ASSERT_FALSE(port.read(s));
  EXPECT_NEAR(s.positionMm[2], 3.0, 1e-9);
}

TEST(ModbusServerPort, RestartedServerServesAReconnectingMaster) {
  ModbusServerPort port(serverSettings());
  ASSERT_FALSE(port.connect());
  const std::uint16_t p = port.boundPort();
  {
    Client master(p);
    auto in = inputBlock(1.0, 2.0, 3.0, 3, 1);
    ASSERT_EQ(modbus_write_registers(master.ctx, 0, 14, in.data()), 14);
    port.disconnect();
    std::array<std::uint16_t, 1> one{};
    EXPECT_EQ(modbus_read_registers(master.ctx, 14, 1, one.data()), -1);
  }
  ASSERT_FALSE(port.connect());
  loop::AxisSample s;
  EXPECT_EQ(port.read(s), Errc::no_master_write);  // a new bank: nothing written yet
  Client again(port.boundPort());
  ASSERT_TRUE(again.connected);
  auto in = inputBlock(4.0, 5.0, 6.0, 3, 2);
  ASSERT_EQ(modbus_write_registers(again.ctx, 0, 14, in.data()), 14);
  ASSERT_TRUE(waitUntil([&] { return !port.read(s); }));
  EXPECT_NEAR(s.positionMm[0], 4.0, 1e-9);
}

TEST(ModbusServerPort, RtuOverAPseudoTerminal) {
  int master = -1, slave = -1;
  char name[256] = {};
  ASSERT_EQ(openpty(&master, &slave, name, nullptr, nullptr), 0);
  json j = test::rtuTransportJson(name);
  j.erase("link_loss_timeouts");
  j["role"] = "server";
  j["registers"].erase("fc23");
  ModbusServerPort port(config::parseModbusSettings(j, "test.json", "transport"));
  std::atomic<int> triggers{0};
  port.setCycleTrigger([&] { ++triggers; });
  ASSERT_FALSE(port.connect());
  ::close(slave);  // the server opened the device itself

  modbus_t* ctx = modbus_new_rtu("/dev/null", 115200, 'N', 8, 1);
  ASSERT_NE(ctx, nullptr);
  modbus_set_slave(ctx, port.settings().slaveId);
  modbus_set_response_timeout(ctx, 2, 0);
  // The master side of a pty is no device one can open: hand libmodbus the descriptor.
  modbus_set_socket(ctx, master);
  auto in = inputBlock(10.0, 20.0, 30.0, 3, 1);
  ASSERT_EQ(modbus_write_registers(ctx, 0, 14, in.data()), 14);
  ASSERT_TRUE(waitUntil([&] { return triggers == 1; }));
  loop::AxisSample s;
  ASSERT_FALSE(port.read(s));
  EXPECT_NEAR(s.positionMm[1], 20.0, 1e-9);
  loop::OffsetCommand c;
  c.offsetMm = {-0.002, 0.0, 0.001};
  c.heartbeat = 9;
  ASSERT_FALSE(port.write(c));
  std::array<std::uint16_t, 8> out{};
  ASSERT_EQ(modbus_read_registers(ctx, 14, 8, out.data()), 8);
  EXPECT_NEAR(int32Mm(&out[0]), -0.002, 1e-9);
  EXPECT_EQ(out[7], 9);
  EXPECT_EQ(modbus_write_register(ctx, 20, 1), -1);
  EXPECT_EQ(errno, EMBXILADD);
  // A function the bank does not serve: refused at once, not after libmodbus' timeout wait.
  modbus_set_response_timeout(ctx, 0, 200000);
  EXPECT_EQ(modbus_read_input_registers(ctx, 0, 1, out.data()), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  // Another slave id gets no answer (a bus may carry several).
  modbus_set_slave(ctx, port.settings().slaveId + 1);
  modbus_set_response_timeout(ctx, 0, 200000);
  EXPECT_EQ(modbus_read_registers(ctx, 14, 8, out.data()), -1);
  EXPECT_EQ(errno, ETIMEDOUT);
  port.disconnect();
  modbus_set_socket(ctx, -1);
  modbus_free(ctx);
  ::close(master);
}

}  // namespace
}  // namespace volcomp::modbus
