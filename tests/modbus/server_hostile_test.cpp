// The server port with a hostile master beside a good one, in process: the good master is
// libmodbus' client (a peer we did not write), the hostile one a raw socket that sends what
// scanners, silent HMIs and broken masters send. Synchronised on conditions only; the hostile
// sender's own pacing is the only sleep.
#include <modbus/modbus.h>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "raw_connection.hpp"
#include "test_maps.hpp"
#include "volcomp/config/modbus_config.hpp"
#include "volcomp/modbus/server_port.hpp"
#include "wait_until.hpp"

namespace volcomp::modbus {
namespace {

using nlohmann::json;
using std::chrono::milliseconds;
using testutil::Bytes;
using testutil::modbusTcpAdu;
using testutil::RawConnection;
using testutil::waitUntil;

ModbusSettings serverSettings(const json& extra) {
  return config::parseModbusSettings(test::serverTransportJson(extra), "test.json", "transport");
}

const Bytes kReadOutputs = {0x03, 0, 14, 0, 8};

/// libmodbus' client reading the outputs as a PLC does, on its own thread, counting failures
/// and the longest transaction.
class GoodMaster {
 public:
  explicit GoodMaster(std::uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    modbus_set_response_timeout(ctx_, 0, 400000);
    connected_ = modbus_connect(ctx_) == 0;
    if (connected_) thread_ = std::thread([this] { run(); });
  }
  ~GoodMaster() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  bool connected() const { return connected_; }
  int transactions() const { return transactions_; }
  int failures() const { return failures_; }
  double longestMs() const { return static_cast<double>(longestUs_.load()) / 1000.0; }

 private:
  void run() {
    std::array<std::uint16_t, 8> out{};
    while (!stop_) {
      const auto t0 = std::chrono::steady_clock::now();
      const bool ok = modbus_read_registers(ctx_, 14, 8, out.data()) == 8;
      const auto us = std::chrono::duration_cast<std::chrono::microseconds>(
                          std::chrono::steady_clock::now() - t0)
                          .count();
      longestUs_ = std::max<long>(longestUs_, static_cast<long>(us));
      ++transactions_;
      if (!ok) ++failures_;
    }
  }
  modbus_t* ctx_;
  bool connected_ = false;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int> transactions_{0};
  std::atomic<int> failures_{0};
  std::atomic<long> longestUs_{0};
};

TEST(ServerHostile, MalformedRequestsAreAnsweredAtOnceWithTheirException) {
  // libmodbus' own replies to these wait out the response timeout first: 5 s here.
  ModbusServerPort port(serverSettings({{"response_timeout_ms", 5000}}));
  ASSERT_FALSE(port.connect());
  RawConnection scanner(port.boundPort());
  ASSERT_TRUE(scanner.connected());
  struct Case {
    Bytes pdu;
    std::uint8_t function;
    std::uint8_t code;
  };
  const std::vector<Case> cases = {
      {{0x2B, 0x0E, 0x01, 0x00}, 0xAB, 1},           // read device identification
      {{0x03, 0, 14, 0, 0}, 0x83, 3},                // FC03, quantity 0
      {{0x10, 0, 0, 0, 2, 6, 0, 1, 0, 2}, 0x90, 3},  // FC16, byte count 6 for 2 registers
      {{0x83, 0, 14, 0, 8}, 0x83, 1},                // an exception's function code as request
      {{0x04, 0, 0, 0, 1}, 0x84, 1},                 // input registers: the bank has none
  };
  std::uint16_t transaction = 1;
  for (const Case& c : cases) {
    ASSERT_TRUE(scanner.send(modbusTcpAdu(transaction, c.pdu)));
    const Bytes reply = scanner.receive(9, milliseconds(2000));
    ASSERT_EQ(reply.size(), 9U) << "function " << int(c.pdu[0]);
    EXPECT_EQ(reply[1], transaction & 0xFF);
    EXPECT_EQ(reply[5], 3);  // length: unit, function, code
    EXPECT_EQ(reply[7], c.function);
    EXPECT_EQ(reply[8], c.code);
    ++transaction;
  }
  // The connection stays usable: a good request is served.
  ASSERT_TRUE(scanner.send(modbusTcpAdu(99, kReadOutputs)));
  const Bytes reply = scanner.receive(9 + 16, milliseconds(2000));
  ASSERT_EQ(reply.size(), 25U);
  EXPECT_EQ(reply[7], 0x03);
  EXPECT_EQ(reply[8], 16);
  EXPECT_EQ(port.counters().refused, cases.size());
}

TEST(ServerHostile, PipelinedRequestsAreAnsweredInOrderAndAStreamOutOfStepIsClosed) {
  ModbusServerPort port(serverSettings({{"max_connections", 2}}));
  ASSERT_FALSE(port.connect());
  RawConnection master(port.boundPort());
  Bytes two = modbusTcpAdu(7, kReadOutputs);
  const Bytes second = modbusTcpAdu(8, {0x03, 0, 0, 0, 2});
  two.insert(two.end(), second.begin(), second.end());
  ASSERT_TRUE(master.send(two));
  const Bytes replies = master.receive(25 + 13, milliseconds(2000));
  ASSERT_EQ(replies.size(), 38U);
  EXPECT_EQ(replies[1], 7);
  EXPECT_EQ(replies[25 + 1], 8);
  EXPECT_EQ(replies[25 + 8], 4);

  RawConnection garbage(port.boundPort());
  ASSERT_TRUE(garbage.send({'G', 'E', 'T', ' ', '/', ' ', 'H', 'T', 'T', 'P'}));
  EXPECT_TRUE(garbage.closedByServer(milliseconds(2000)));
  EXPECT_EQ(port.counters().droppedConnections, 1U);
}

TEST(ServerHostile, ABadMasterNeverStallsAGoodOne) {
  // With libmodbus' own receive and exception replies, each of these held every connection for
  // up to the response timeout (1 s here); the good master gives up after 0.4 s.
  ModbusServerPort port(serverSettings({{"max_connections", 3}, {"response_timeout_ms", 1000}}));
  ASSERT_FALSE(port.connect());
  GoodMaster good(port.boundPort());
  ASSERT_TRUE(good.connected());
  ASSERT_TRUE(waitUntil([&] { return good.transactions() >= 20; }));

  // A slow sender: one byte of a request every 100 ms; cut 1 s after its first byte.
  RawConnection slow(port.boundPort());
  const Bytes request = modbusTcpAdu(1, kReadOutputs);
  bool cut = false;
  for (std::size_t i = 0; i < request.size() && !cut; ++i) {
    cut = !slow.send({request[i]});
    std::this_thread::sleep_for(milliseconds(100));  // the hostile sender's pace
  }
  EXPECT_TRUE(cut || slow.closedByServer(milliseconds(2000)));
  EXPECT_EQ(port.counters().droppedConnections, 1U);

  // A scanner probing functions the bank does not serve, a request every 30 ms.
  RawConnection scanner(port.boundPort());
  for (std::uint16_t t = 0; t < 20; ++t) {
    ASSERT_TRUE(
        scanner.send(modbusTcpAdu(t, {static_cast<std::uint8_t>(0x2B + t), 0x0E, 0x01, 0x00})));
    EXPECT_EQ(scanner.receive(9, milliseconds(2000)).size(), 9U);
    std::this_thread::sleep_for(milliseconds(30));
  }
  const int before = good.transactions();
  ASSERT_TRUE(waitUntil([&] { return good.transactions() >= before + 20; }));
  EXPECT_EQ(good.failures(), 0) << "longest transaction " << good.longestMs() << " ms";
}

TEST(ServerHostile, ASilentConnectionGivesItsSlotToANewMasterAndAPollingOneKeepsIt) {
  ModbusServerPort port(serverSettings({{"max_connections", 1}, {"takeover_after_ms", 300}}));
  ASSERT_FALSE(port.connect());
  // An HMI that connects and goes quiet, or a PLC that rebooted without closing its socket.
  RawConnection silent(port.boundPort());
  ASSERT_TRUE(waitUntil([&] { return port.counters().connections == 1; }));
  // The PLC reconnects as it does, until it is served.
  std::array<std::uint16_t, 8> out{};
  bool served = false;
  ASSERT_TRUE(waitUntil(
      [&] {
        modbus_t* ctx = modbus_new_tcp("127.0.0.1", port.boundPort());
        modbus_set_response_timeout(ctx, 0, 200000);
        served = modbus_connect(ctx) == 0 && modbus_read_registers(ctx, 14, 8, out.data()) == 8;
        modbus_close(ctx);
        modbus_free(ctx);
        return served;
      },
      milliseconds(5000)));
  EXPECT_EQ(port.counters().replacedConnections, 1U);
  EXPECT_TRUE(silent.closedByServer(milliseconds(2000)));

  // A master that polls is never displaced: the newcomer is refused.
  GoodMaster plc(port.boundPort());
  ASSERT_TRUE(waitUntil([&] { return plc.transactions() >= 50; }));
  const auto refusedBefore = port.counters().refusedConnections.load();
  RawConnection intruder(port.boundPort());
  EXPECT_TRUE(intruder.closedByServer(milliseconds(2000)));
  EXPECT_EQ(port.counters().refusedConnections, refusedBefore + 1);
  const int before = plc.transactions();
  ASSERT_TRUE(waitUntil([&] { return plc.transactions() >= before + 20; }));
  EXPECT_EQ(plc.failures(), 0);
}

TEST(ServerHostile, AConnectionSilentForTheIdleTimeoutIsClosed) {
  ModbusServerPort port(serverSettings({{"idle_timeout_s", 1}}));
  ASSERT_FALSE(port.connect());
  RawConnection quiet(port.boundPort());
  ASSERT_TRUE(quiet.send(modbusTcpAdu(1, kReadOutputs)));
  ASSERT_EQ(quiet.receive(25, milliseconds(2000)).size(), 25U);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(quiet.closedByServer(milliseconds(5000)));
  EXPECT_GE(std::chrono::steady_clock::now() - t0, milliseconds(900));
  EXPECT_EQ(port.counters().droppedConnections, 1U);
}

/// The kernel's timer on the server's end of a loopback connection (/proc/net/tcp: local port
/// `serverPort`, remote port `clientPort`): {kind, clock ticks until it fires}; kind 2 is the
/// keepalive timer. {-1, 0} when the socket is not listed.
std::pair<int, long> serverSideTimer(std::uint16_t serverPort, std::uint16_t clientPort) {
  std::ifstream in("/proc/net/tcp");
  std::string line;
  std::getline(in, line);  // the header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string slot, local, remote, state, queues, timer;
    fields >> slot >> local >> remote >> state >> queues >> timer;
    const auto port = [](const std::string& address) {
      return static_cast<std::uint16_t>(
          std::stoul(address.substr(address.find(':') + 1), nullptr, 16));
    };
    if (port(local) != serverPort || port(remote) != clientPort) continue;
    const auto colon = timer.find(':');
    return {std::stoi(timer.substr(0, colon), nullptr, 16),
            std::stol(timer.substr(colon + 1), nullptr, 16)};
  }
  return {-1, 0};
}

TEST(ServerHostile, KeepaliveProbesAPeerThatGoesSilent) {
  ModbusServerPort port(serverSettings({{"keepalive_s", 7}}));
  ASSERT_FALSE(port.connect());
  RawConnection peer(port.boundPort());
  ASSERT_TRUE(waitUntil([&] { return port.counters().connections == 1; }));
  std::pair<int, long> timer;
  ASSERT_TRUE(waitUntil([&] {
    timer = serverSideTimer(port.boundPort(), peer.localPort());
    return timer.first == 2;
  })) << "timer kind "
      << timer.first;
  EXPECT_GT(timer.second, 0);
  EXPECT_LE(timer.second, 7 * sysconf(_SC_CLK_TCK));  // the first probe within keepalive_s

  ModbusServerPort off(serverSettings({{"keepalive_s", 0}}));
  ASSERT_FALSE(off.connect());
  RawConnection quiet(off.boundPort());
  ASSERT_TRUE(waitUntil([&] { return off.counters().connections == 1; }));
  EXPECT_EQ(serverSideTimer(off.boundPort(), quiet.localPort()).first, 0);
}

}  // namespace
}  // namespace volcomp::modbus
