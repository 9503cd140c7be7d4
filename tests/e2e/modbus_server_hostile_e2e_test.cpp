// The server role on a shop network, end to end: volcompd as a process, a PLC (libmodbus'
// client, a peer we did not write) running its cycle, and beside it what every shop network has:
// a scanner probing function codes, a master sending its bytes slowly, an HMI that connects and
// goes quiet, a master sending NaN. The PLC's transactions must not slow down (p99 within 2x of
// its own without the hostile ones, measured in alternating blocks of the same run) and the
// daemon must not fault because of another connection.
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <thread>

#include "modbus_server_fixture.hpp"
#include "raw_connection.hpp"

namespace volcomp::e2e {
namespace {

using testutil::Bytes;
using testutil::modbusTcpAdu;
using testutil::RawConnection;

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

/// A scanner and a slow sender on their own connections, one step every 30 ms while running.
class HostileNeighbours {
 public:
  explicit HostileNeighbours(int port) : port_(static_cast<std::uint16_t>(port)) {
    thread_ = std::thread([this] { run(); });
  }
  ~HostileNeighbours() {
    stop_ = true;
    thread_.join();
  }
  void setActive(bool active) { active_ = active; }
  int refusalsAnswered() const { return refusalsAnswered_; }
  int slowSendersCut() const { return slowSendersCut_; }

 private:
  void run() {
    // The hostile peers are other machines on the network: their own CPU time must not be taken
    // from the PLC and the daemon on this one (the daemon's work serving them is what is tested).
    sched_param idle{};
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &idle);
    const std::vector<Bytes> probes = {
        {0x2B, 0x0E, 0x01, 0x00},           // read device identification
        {0x03, 0, 14, 0, 0},                // FC03, quantity 0
        {0x10, 0, 0, 0, 2, 6, 0, 1, 0, 2},  // FC16, byte count 6 for 2 registers
        {0x83, 0, 14, 0, 8},                // an exception's function code as a request
        {0x01, 0, 0, 0, 8},                 // coils
    };
    const Bytes slowRequest = modbusTcpAdu(1, {0x03, 0, 14, 0, 8});
    std::unique_ptr<RawConnection> scanner, slow;
    std::size_t sent = 0;
    std::uint16_t transaction = 0;
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));  // the hostile pace
      if (!active_) continue;
      if (!scanner) scanner = std::make_unique<RawConnection>(port_);
      const Bytes& probe = probes[transaction % probes.size()];
      if (scanner->send(modbusTcpAdu(++transaction, probe)) &&
          scanner->receive(9, std::chrono::milliseconds(1000)).size() == 9) {
        ++refusalsAnswered_;
      } else {
        scanner.reset();
      }
      if (!slow) {
        slow = std::make_unique<RawConnection>(port_);
        sent = 0;
      }
      if (sent >= slowRequest.size() || !slow->send({slowRequest[sent++]})) {
        ++slowSendersCut_;
        slow.reset();
      }
    }
  }
  std::uint16_t port_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> active_{false};
  std::atomic<int> refusalsAnswered_{0};
  std::atomic<int> slowSendersCut_{0};
};

TEST_F(ModbusServerTest, HostileNeighboursNeitherSlowThePlcNorFaultTheDaemon) {
  json config = serverConfig();
  config["transport"]["max_connections"] = 3;
  const int port = startServer(config);
  ASSERT_GT(port, 0);
  Master plc = Master::tcp(port);
  ASSERT_TRUE(plc.connect());
  run(plc, 0, 150);  // into active, offsets ramped in
  ASSERT_NE(plc.reads.back().status & kActive, 0u) << daemonLog();

  HostileNeighbours hostile(port);
  std::vector<double> quietMs, hostileMs;
  // A PLC cycle every 10 ms, in 20 alternating blocks: 500 transactions each way, so that the
  // p99 is the 5th longest, not one scheduling hiccup of this machine.
  Pacer pacer(std::chrono::milliseconds(10));
  int cycle = 150;
  for (int block = 0; block < 20; ++block) {
    const bool active = block % 2 == 1;
    hostile.setActive(active);
    for (int i = 0; i < 50; ++i, ++cycle) {
      pacer.tick();
      const auto t0 = std::chrono::steady_clock::now();
      ASSERT_TRUE(plc.cycle(pathAt(cycle, 100), kEnabledHomed)) << "cycle " << cycle;
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      (active ? hostileMs : quietMs).push_back(ms);
      ASSERT_EQ(plc.reads.back().status & kFault, 0u) << "cycle " << cycle << "\n" << daemonLog();
    }
  }
  hostile.setActive(false);
  EXPECT_GT(hostile.refusalsAnswered(), 50);
  EXPECT_GT(hostile.slowSendersCut(), 5);
  const double quietP99 = percentile(quietMs, 0.99);
  const double hostileP99 = percentile(hostileMs, 0.99);
  std::printf("PLC transaction p99 %.3f ms alone, %.3f ms beside the hostile connections\n",
              quietP99, hostileP99);
  RecordProperty("plc_p99_quiet_ms", std::to_string(quietP99));
  RecordProperty("plc_p99_hostile_ms", std::to_string(hostileP99));
  EXPECT_LE(hostileP99, 2.0 * quietP99)
      << "PLC transaction p99: " << quietP99 << " ms alone, " << hostileP99
      << " ms beside the hostile connections (median " << percentile(quietMs, 0.5) << " / "
      << percentile(hostileMs, 0.5) << " ms)";
  expectReadsWithinLimits(plc.reads);
  expectOffsetsOfTheModel(plc);
  EXPECT_NE(daemonLog().find("request still incomplete"), std::string::npos) << daemonLog();
  stopDaemon();
}

TEST_F(ModbusServerTest, ARebootedPlcGetsItsSlotBackFromTheConnectionItLeftOpen) {
  // The shipped example: one connection. The PLC reboots without closing its socket: the old
  // connection stays open and silent (as an HMI that connects and goes quiet would).
  const int port = startServer(serverConfig());
  ASSERT_GT(port, 0);
  RawConnection leftOpen(static_cast<std::uint16_t>(port));
  ASSERT_TRUE(leftOpen.send(modbusTcpAdu(1, {0x03, 0, 14, 0, 8})));
  ASSERT_EQ(leftOpen.receive(25, std::chrono::milliseconds(2000)).size(), 25U);
  const auto rebooted = std::chrono::steady_clock::now();
  Master plc = Master::tcp(port);
  Pacer pacer(std::chrono::milliseconds(10));
  const bool served = testutil::waitUntil(
      [&] {
        pacer.tick();
        return plc.cycle(kFrom, kEnabledHomed);
      },
      10s);
  ASSERT_TRUE(served) << daemonLog();
  const double waitedS =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - rebooted).count();
  EXPECT_LT(waitedS, 3.0);  // takeover_after_ms 1 s, plus the PLC's reconnect attempts
  EXPECT_TRUE(leftOpen.closedByServer(std::chrono::milliseconds(2000)));
  EXPECT_NE(daemonLog().find("its slot taken by"), std::string::npos) << daemonLog();
  run(plc, 0, 150);
  EXPECT_NE(plc.reads.back().status & kActive, 0u) << daemonLog();
  stopDaemon();
}

TEST_F(ModbusServerTest, ANanPositionIsInvalidInputLatched) {
  // Position X as a float32 in mm: the one type that can carry NaN.
  json config = serverConfig();
  config["transport"]["registers"]["position"]["X"] = {
      {"address", 0}, {"type", "float32"}, {"counts_per_mm", 1}};
  const int port = startServer(config);
  ASSERT_GT(port, 0);
  Master plc = Master::tcp(port);
  ASSERT_TRUE(plc.connect());
  std::uint16_t life = 0;
  const auto writeInputs = [&](float x) {
    std::array<std::uint16_t, 14> in{};
    std::uint32_t bits = 0;
    std::memcpy(&bits, &x, sizeof bits);
    in[0] = static_cast<std::uint16_t>(bits >> 16);
    in[1] = static_cast<std::uint16_t>(bits & 0xFFFF);
    putInt32(&in[2], kFrom[1]);
    putInt32(&in[4], kFrom[2]);
    in[6] = kEnabledHomed;
    in[7] = ++life;
    return modbus_write_registers(plc.ctx(), 0, 14, in.data()) == 14;
  };
  const auto status = [&] {
    std::array<std::uint16_t, 8> out{};
    return modbus_read_registers(plc.ctx(), 14, 8, out.data()) == 8 ? out[6] : 0xFFFFu;
  };
  Pacer pacer(std::chrono::milliseconds(10));
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        pacer.tick();
        return writeInputs(static_cast<float>(kFrom[0])) && (status() & kActive) != 0;
      },
      10s))
      << daemonLog();
  constexpr unsigned kLatched = 1u << 10;
  const auto faultCode = [](unsigned s) { return (s >> 12) & 0xF; };
  unsigned seen = 0;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        pacer.tick();
        seen = status();
        return writeInputs(std::numeric_limits<float>::quiet_NaN()) && (seen & kFault) != 0;
      },
      10s))
      << daemonLog();
  EXPECT_EQ(faultCode(seen), 3u) << "status " << seen;
  // Good positions again: the fault stays latched until acknowledged.
  for (int i = 0; i < 20; ++i) {
    pacer.tick();
    ASSERT_TRUE(writeInputs(static_cast<float>(kFrom[0])));
  }
  seen = status();
  EXPECT_EQ(faultCode(seen), 3u) << "status " << seen;
  EXPECT_NE(seen & kLatched, 0u) << "status " << seen;
  stopDaemon();
}

}  // namespace
}  // namespace volcomp::e2e
