// The server role's pure parts: the bank layout, the refusals of requests (function, length,
// quantity, address) and the position-set tracker; and the server-role keys of the transport
// section (typed errors with key paths).
#include "volcomp/modbus/server_bank.hpp"

#include <arpa/inet.h>

#include <array>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_maps.hpp"
#include "volcomp/config/modbus_config.hpp"

namespace volcomp::modbus {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;

json serverJson() {
  return test::serverTransportJson();
}

ModbusSettings parse(const json& j) {
  return config::parseModbusSettings(j, "plant.json", "transport");
}

void expectRejected(const json& section, const std::string& keyPath, const std::string& message) {
  try {
    parse(section);
    FAIL() << "accepted: " << section.dump();
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), keyPath) << e.what();
    EXPECT_THAT(e.message(), HasSubstr(message)) << e.what();
  }
}

std::array<std::uint8_t, 9> pdu(std::uint8_t fc, std::uint16_t a, std::uint16_t b,
                                std::uint16_t c = 0, std::uint16_t d = 0) {
  return {fc,
          static_cast<std::uint8_t>(a >> 8),
          static_cast<std::uint8_t>(a & 0xFF),
          static_cast<std::uint8_t>(b >> 8),
          static_cast<std::uint8_t>(b & 0xFF),
          static_cast<std::uint8_t>(c >> 8),
          static_cast<std::uint8_t>(c & 0xFF),
          static_cast<std::uint8_t>(d >> 8),
          static_cast<std::uint8_t>(d & 0xFF)};
}

TEST(ServerBank, LayoutOfTheExampleMap) {
  const ServerLayout l = layoutServerBank(parse(serverJson()).registers);
  EXPECT_EQ(l.bank.start, 0);
  EXPECT_EQ(l.bank.count, 22);
  EXPECT_EQ(l.masterWrite.start, 0);
  EXPECT_EQ(l.masterWrite.count, 14);
  EXPECT_EQ(l.output.start, 14);
  EXPECT_EQ(l.output.count, 8);
}

TEST(ServerBank, OutputsBelowTheInputsShiftTheBankStart) {
  json j = serverJson();
  j["registers"]["offset"] = {
      {"X", {{"address", 100}}}, {"Y", {{"address", 102}}}, {"Z", {{"address", 104}}}};
  j["registers"]["status"] = 106;
  j["registers"]["heartbeat"] = 107;
  for (const char* axis : {"X", "Y", "Z"}) {
    j["registers"]["position"][axis]["address"] = 200 + 2 * (axis[0] - 'X');
  }
  j["registers"]["enable"]["address"] = 206;
  j["registers"]["homed"]["address"] = 206;
  j["registers"]["sequence"]["address"] = 207;
  j["registers"].erase("applied_offset");
  const ServerLayout l = layoutServerBank(parse(j).registers);
  EXPECT_EQ(l.bank.start, 100);
  EXPECT_EQ(l.bank.count, 108);
  EXPECT_EQ(l.masterWrite.start, 200);
  EXPECT_EQ(l.masterWrite.count, 8);
}

TEST(ServerBank, ParsesRequestRanges) {
  const auto read = parseServerRequest(pdu(0x03, 14, 8));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->read.start, 14);
  EXPECT_EQ(read->read.count, 8);
  EXPECT_EQ(read->write.count, 0);
  const auto single = parseServerRequest(pdu(0x06, 7, 0x1234));
  ASSERT_TRUE(single);
  EXPECT_EQ(single->write.start, 7);
  EXPECT_EQ(single->write.count, 1);
  const auto multiple = parseServerRequest(pdu(0x10, 0, 6));
  ASSERT_TRUE(multiple);
  EXPECT_EQ(multiple->write.count, 6);
  const auto both = parseServerRequest(pdu(0x17, 14, 8, 0, 14));
  ASSERT_TRUE(both);
  EXPECT_EQ(both->read.start, 14);
  EXPECT_EQ(both->read.count, 8);
  EXPECT_EQ(both->write.start, 0);
  EXPECT_EQ(both->write.count, 14);
  const auto mask = parseServerRequest(pdu(0x16, 6, 0xFFFE, 0x0001));
  ASSERT_TRUE(mask);
  EXPECT_EQ(mask->write.start, 6);
  EXPECT_EQ(mask->write.count, 1);
  // Too short for its function; other functions carry no range.
  EXPECT_FALSE(parseServerRequest(std::span(pdu(0x10, 0, 6).data(), 3)));
  EXPECT_FALSE(parseServerRequest({}));
  const auto coils = parseServerRequest(pdu(0x01, 0, 8));
  ASSERT_TRUE(coils);
  EXPECT_EQ(coils->read.count + coils->write.count, 0);
}

/// A request PDU exactly as a master sends it: FC03 (address, quantity), FC06 (address, value),
/// FC16 (address, quantity, 2 x quantity data bytes), FC22 (address, masks), FC23 (read address
/// and quantity, write address and quantity, data).
std::vector<std::uint8_t> request(std::uint8_t fc, std::uint16_t a, std::uint16_t b,
                                  std::uint16_t c = 0, std::uint16_t d = 0) {
  const auto words = [](std::initializer_list<std::uint16_t> w) {
    std::vector<std::uint8_t> out;
    for (std::uint16_t v : w) {
      out.push_back(static_cast<std::uint8_t>(v >> 8));
      out.push_back(static_cast<std::uint8_t>(v & 0xFF));
    }
    return out;
  };
  std::vector<std::uint8_t> r{fc};
  const auto append = [&](const std::vector<std::uint8_t>& bytes) {
    r.insert(r.end(), bytes.begin(), bytes.end());
  };
  switch (fc) {
    case 0x10:
      append(words({a, b}));
      r.push_back(static_cast<std::uint8_t>(2 * b));
      r.resize(r.size() + 2U * b, 0);
      break;
    case 0x16:
      append(words({a, b, c}));
      break;
    case 0x17:
      append(words({a, b, c, d}));
      r.push_back(static_cast<std::uint8_t>(2 * d));
      r.resize(r.size() + 2U * d, 0);
      break;
    default:
      append(words({a, b}));
  }
  return r;
}

TEST(ServerBank, RefusesWritesOutsideTheInputBlockAndReadsOutsideTheBank) {
  const ServerLayout l = layoutServerBank(parse(serverJson()).registers);
  const auto check = [&](const std::vector<std::uint8_t>& p) { return refuseRequest(l, p); };
  EXPECT_EQ(check(request(0x10, 0, 14)), 0);                    // the whole input block
  EXPECT_EQ(check(request(0x10, 0, 6)), 0);                     // the positions
  EXPECT_EQ(check(request(0x06, 13, 1)), 0);                    // the last input register
  EXPECT_EQ(check(request(0x03, 0, 22)), 0);                    // the whole bank
  EXPECT_EQ(check(request(0x03, 14, 8)), 0);                    // the outputs
  EXPECT_EQ(check(request(0x16, 6, 0xFFFE, 1)), 0);             // mask write of the flags
  EXPECT_EQ(check(request(0x06, 14, 1)), kIllegalDataAddress);  // an offset output
  EXPECT_EQ(check(request(0x10, 12, 4)), kIllegalDataAddress);  // runs into the outputs
  EXPECT_EQ(check(request(0x10, 21, 1)), kIllegalDataAddress);  // heartbeat
  EXPECT_EQ(check(request(0x06, 30, 1)), kIllegalDataAddress);  // outside the bank
  EXPECT_EQ(check(request(0x03, 20, 3)), kIllegalDataAddress);  // runs past the bank
  EXPECT_EQ(check(request(0x03, 100, 1)), kIllegalDataAddress);
  EXPECT_EQ(check(request(0x16, 20, 1, 0)), kIllegalDataAddress);  // mask write onto status
  EXPECT_EQ(check(request(0x17, 14, 8, 0, 14)), 0);  // FC23: write inputs, read outputs
  EXPECT_EQ(check(request(0x17, 14, 8, 14, 2)), kIllegalDataAddress);
  EXPECT_EQ(check(request(0x17, 14, 9, 0, 2)), kIllegalDataAddress);
}

TEST(ServerBank, RefusesFunctionsAndMalformedRequestsAsTheProtocolOrdersIt) {
  const ServerLayout l = layoutServerBank(parse(serverJson()).registers);
  const auto check = [&](std::vector<std::uint8_t> p) { return refuseRequest(l, p); };
  // Functions the bank does not serve, including a code with the high bit (no request has it).
  for (const int fc : {0x01, 0x02, 0x04, 0x05, 0x07, 0x0F, 0x11, 0x2B, 0x83, 0x90}) {
    EXPECT_EQ(check(request(static_cast<std::uint8_t>(fc), 0, 1)), kIllegalFunction) << int(fc);
  }
  EXPECT_EQ(check({}), kIllegalFunction);
  // Quantities of 0 or beyond what one reply or request carries; the function comes first, the
  // quantity before the address.
  EXPECT_EQ(check(request(0x03, 0, 0)), kIllegalDataValue);
  EXPECT_EQ(check(request(0x03, 0, 126)), kIllegalDataValue);
  EXPECT_EQ(check(request(0x03, 500, 0)), kIllegalDataValue);
  EXPECT_EQ(check(request(0x10, 0, 0)), kIllegalDataValue);
  EXPECT_EQ(check(request(0x17, 14, 0, 0, 2)), kIllegalDataValue);
  EXPECT_EQ(check(request(0x17, 14, 8, 0, 0)), kIllegalDataValue);
  // A byte count that does not match the quantity, or data that does not match the byte count.
  auto fc16 = request(0x10, 0, 6);
  fc16[5] = 10;
  EXPECT_EQ(check(fc16), kIllegalDataValue);
  fc16 = request(0x10, 0, 6);
  fc16.pop_back();
  EXPECT_EQ(check(fc16), kIllegalDataValue);
  fc16 = request(0x10, 0, 6);
  fc16.push_back(0);
  EXPECT_EQ(check(fc16), kIllegalDataValue);
  auto fc23 = request(0x17, 14, 8, 0, 14);
  fc23[9] = 2;
  EXPECT_EQ(check(fc23), kIllegalDataValue);
  // Fixed-length functions with a byte too few or too many.
  auto fc03 = request(0x03, 14, 8);
  fc03.push_back(0);
  EXPECT_EQ(check(fc03), kIllegalDataValue);
  EXPECT_EQ(check({0x06, 0, 1, 0}), kIllegalDataValue);
  EXPECT_EQ(check({0x16, 0, 6, 0xFF, 0xFE}), kIllegalDataValue);
}

TEST(ServerBank, OutputsInsideTheInputSpanAreStillRefused) {
  // Inputs at 0..5 and 30..33 around outputs at 10..17: the input block spans 0..33.
  json j = serverJson();
  j["registers"]["enable"]["address"] = 30;
  j["registers"]["homed"]["address"] = 30;
  j["registers"]["sequence"]["address"] = 31;
  j["registers"].erase("applied_offset");
  j["registers"]["offset"] = {
      {"X", {{"address", 10}}}, {"Y", {{"address", 12}}}, {"Z", {{"address", 14}}}};
  j["registers"]["status"] = 16;
  j["registers"]["heartbeat"] = 17;
  const ServerLayout l = layoutServerBank(parse(j).registers);
  EXPECT_EQ(refuseRequest(l, request(0x06, 20, 1)), 0);  // a gap of the block
  EXPECT_EQ(refuseRequest(l, request(0x10, 8, 4)), kIllegalDataAddress);
}

TEST(ServerBank, PositionSetCompletesWhenEveryPositionRegisterIsWritten) {
  PositionWriteTracker t(parse(serverJson()).registers);
  EXPECT_TRUE(t.onWrite({0, 14}));  // one write of the whole input block
  EXPECT_FALSE(t.onWrite({6, 2}));  // flags and life counter only
  EXPECT_FALSE(t.onWrite({0, 2}));  // X
  EXPECT_FALSE(t.onWrite({3, 1}));  // Y low word
  EXPECT_FALSE(t.onWrite({2, 1}));  // Y high word
  EXPECT_TRUE(t.onWrite({4, 2}));   // Z completes the set
  EXPECT_FALSE(t.onWrite({4, 2}));  // a new set starts
  t.reset();
  EXPECT_FALSE(t.onWrite({0, 4}));
  EXPECT_TRUE(t.onWrite({4, 4}));
}

TEST(ServerBank, SixteenBitPositionsInSeparateWrites) {
  json j = serverJson();
  j["registers"]["position"] = {{"X", {{"address", 0}, {"type", "int16"}}},
                                {"Y", {{"address", 1}, {"type", "int16"}}},
                                {"Z", {{"address", 2}, {"type", "int16"}}}};
  PositionWriteTracker t(parse(j).registers);
  EXPECT_FALSE(t.onWrite({0, 1}));
  EXPECT_FALSE(t.onWrite({1, 1}));
  EXPECT_TRUE(t.onWrite({2, 1}));
}

TEST(ServerBank, AllowedClients) {
  const std::vector<std::uint32_t> none;
  const std::uint32_t local = htonl(INADDR_LOOPBACK);
  EXPECT_TRUE(clientAllowed(local, none));
  const std::vector<std::uint32_t> list{inet_addr("192.168.0.20"), local};
  EXPECT_TRUE(clientAllowed(local, list));
  EXPECT_FALSE(clientAllowed(inet_addr("192.168.0.21"), list));
}

TEST(ServerConfig, DefaultsAndKeys) {
  const ModbusSettings d = parse(serverJson());
  EXPECT_EQ(d.role, ModbusRole::Server);
  EXPECT_EQ(d.server.listenAddress, "127.0.0.1");
  EXPECT_TRUE(d.server.allowedClients.empty());
  EXPECT_EQ(d.server.maxConnections, 1);
  EXPECT_EQ(d.server.trigger, CycleTrigger::Write);
  EXPECT_EQ(std::get<TcpLink>(d.link).port, 0);  // any free port

  json j = serverJson();
  j["listen_address"] = "0.0.0.0";
  j["allowed_clients"] = {"192.168.0.20", "10.1.2.3"};
  j["max_connections"] = 3;
  j["cycle_trigger"] = "timer";
  const ModbusSettings s = parse(j);
  EXPECT_EQ(s.server.listenAddress, "0.0.0.0");
  ASSERT_EQ(s.server.allowedClients.size(), 2U);
  EXPECT_EQ(s.server.allowedClients[1], inet_addr("10.1.2.3"));
  EXPECT_EQ(s.server.maxConnections, 3);
  EXPECT_EQ(s.server.trigger, CycleTrigger::Timer);
  // Connection upkeep: defaults, then each set.
  EXPECT_EQ(s.server.idleTimeoutS, 60);
  EXPECT_EQ(s.server.keepaliveS, 10);
  EXPECT_EQ(s.server.takeoverAfterMs, 1000);
  j["idle_timeout_s"] = 0;
  j["keepalive_s"] = 5;
  j["takeover_after_ms"] = 250;
  const ModbusSettings t = parse(j);
  EXPECT_EQ(t.server.idleTimeoutS, 0);
  EXPECT_EQ(t.server.keepaliveS, 5);
  EXPECT_EQ(t.server.takeoverAfterMs, 250);

  // The client role is the default and unchanged.
  EXPECT_EQ(parse(test::tcpTransportJson(1502)).role, ModbusRole::Client);
}

TEST(ServerConfig, RtuServer) {
  json j = test::rtuTransportJson("/dev/ttyUSB0");
  j.erase("link_loss_timeouts");
  j["role"] = "server";
  j["registers"].erase("fc23");
  j["cycle_trigger"] = "timer";
  const ModbusSettings s = parse(j);
  EXPECT_EQ(s.role, ModbusRole::Server);
  EXPECT_EQ(s.server.trigger, CycleTrigger::Timer);
  j["max_connections"] = 2;
  expectRejected(j, "transport.max_connections", "");
}

TEST(ServerConfig, TypedErrorsWithKeyPaths) {
  json j = serverJson();
  j["role"] = "master";
  expectRejected(j, "transport.role", "client");

  j = serverJson();
  j["host"] = "127.0.0.1";
  expectRejected(j, "transport.host", "");

  j = serverJson();
  j["listen_address"] = "localhost";
  expectRejected(j, "transport.listen_address", "IPv4 address");

  j = serverJson();
  j["allowed_clients"] = {"192.168.0.20", "192.168.0.300"};
  expectRejected(j, "transport.allowed_clients[1]", "IPv4 address");

  j = serverJson();
  j["allowed_clients"] = "192.168.0.20";
  expectRejected(j, "transport.allowed_clients", "array");

  j = serverJson();
  j["max_connections"] = 0;
  expectRejected(j, "transport.max_connections", "");

  j = serverJson();
  j["idle_timeout_s"] = -1;
  expectRejected(j, "transport.idle_timeout_s", "");
  j = serverJson();
  j["keepalive_s"] = 1.5;
  expectRejected(j, "transport.keepalive_s", "");
  j = serverJson();
  j["takeover_after_ms"] = 0;
  expectRejected(j, "transport.takeover_after_ms", "");

  j = serverJson();
  j["cycle_trigger"] = "poll";
  expectRejected(j, "transport.cycle_trigger", "write");

  j = serverJson();
  j["registers"]["position"]["Y"]["table"] = "input";
  expectRejected(j, "transport.registers.position.Y.table", "holding register");

  j = serverJson();
  j["registers"]["applied_offset"] = {
      {"X", {{"address", 14}}}, {"Y", {{"address", 16}}}, {"Z", {{"address", 18}}}};
  expectRejected(j, "transport.registers.applied_offset.X", "master writes");

  // Client-role keys stay client-role keys.
  j = test::tcpTransportJson(1502);
  j["max_connections"] = 2;
  expectRejected(j, "transport.max_connections", "");
}

}  // namespace
}  // namespace volcomp::modbus
