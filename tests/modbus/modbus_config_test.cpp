#include "volcomp/config/modbus_config.hpp"

#include <array>
#include <cmath>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_maps.hpp"
#include "volcomp/modbus/register_plan.hpp"

namespace volcomp::config {
namespace {

using modbus::RegisterTable;
using modbus::RegisterType;
using modbus::RtuLink;
using modbus::TcpLink;
using modbus::WordOrder;
using nlohmann::json;
using ::testing::HasSubstr;

/// Expects parseModbusSettings to throw a ConfigError whose key path and message contain the given
/// fragments.
void expectRejected(const json& section, const std::string& keyPath, const std::string& message) {
  try {
    parseModbusSettings(section, "plant.json", "transport");
    FAIL() << "accepted: " << section.dump();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "plant.json");
    EXPECT_EQ(e.keyPath(), keyPath) << e.what();
    EXPECT_THAT(e.message(), HasSubstr(message)) << e.what();
  }
}

json base() {
  return test::tcpTransportJson(1502);
}

TEST(ModbusConfig, ParsesTheTestLayout) {
  const modbus::ModbusSettings c = parseModbusSettings(base(), "plant.json", "transport");
  const auto& tcp = std::get<TcpLink>(c.link);
  EXPECT_EQ(tcp.host, "127.0.0.1");
  EXPECT_EQ(tcp.port, 1502);
  EXPECT_EQ(c.slaveId, 1);
  EXPECT_DOUBLE_EQ(c.responseTimeoutMs, 100.0);
  EXPECT_EQ(c.linkLossTimeouts, 2);
  const auto& m = c.registers;
  EXPECT_EQ(m.position[1].address, 2);
  EXPECT_EQ(m.position[1].format.type, RegisterType::Int32);
  EXPECT_DOUBLE_EQ(m.position[1].format.countsPerMm, 10000.0);
  EXPECT_EQ(m.homed.bit, 1);
  ASSERT_TRUE(m.sequence.has_value());
  ASSERT_TRUE(m.appliedOffset.has_value());
  EXPECT_EQ((*m.appliedOffset)[2].address, 12);
  EXPECT_EQ(m.heartbeatAddress, 21);
  EXPECT_FALSE(m.fc23);

  // Inputs in one FC03 (0..13), outputs in one FC16 (14..21), no input registers.
  const modbus::RegisterPlan plan = modbus::planRegisters(m);
  EXPECT_EQ(plan.holdingRead.start, 0);
  EXPECT_EQ(plan.holdingRead.count, 14);
  EXPECT_EQ(plan.inputRead.count, 0);
  EXPECT_EQ(plan.write.start, 14);
  EXPECT_EQ(plan.write.count, 8);
}

TEST(ModbusConfig, PerFieldOverridesAndRtu) {
  json s = test::rtuTransportJson("/dev/ttyUSB0");
  s["parity"] = "E";
  s["stop_bits"] = 2;
  s["registers"]["position"]["X"] = {{"address", 100},  {"table", "input"},   {"type", "float32"},
                                     {"order", "CDAB"}, {"counts_per_mm", 1}, {"sign", -1}};
  const modbus::ModbusSettings c = parseModbusSettings(s, "plant.json", "transport");
  const auto& rtu = std::get<RtuLink>(c.link);
  EXPECT_EQ(rtu.device, "/dev/ttyUSB0");
  EXPECT_EQ(rtu.parity, 'E');
  EXPECT_EQ(rtu.stopBits, 2);
  EXPECT_EQ(c.slaveId, 7);
  const auto& x = c.registers.position[0];
  EXPECT_EQ(x.table, RegisterTable::Input);
  EXPECT_EQ(x.format.type, RegisterType::Float32);
  EXPECT_EQ(x.format.order, WordOrder::CDAB);
  EXPECT_EQ(x.format.sign, -1);
  const modbus::RegisterPlan plan = modbus::planRegisters(c.registers);
  EXPECT_EQ(plan.inputRead.start, 100);
  EXPECT_EQ(plan.inputRead.count, 2);
  EXPECT_EQ(plan.holdingRead.start, 2);  // Y, Z, flags, counter, applied offsets: 2..13
  EXPECT_EQ(plan.holdingRead.count, 12);
}

TEST(ModbusConfig, AppliedOffsetMayReadBackTheOutputsThemselves) {
  json s = base();
  s["registers"]["applied_offset"] = s["registers"]["offset"];
  EXPECT_NO_THROW(parseModbusSettings(s, "plant.json", "transport"));
}

// A NaN or infinity in a float input is the controller's data, not a failed read: it reaches the
// loop as NaN (which faults it as invalid input, latched), and the other inputs are decoded.
TEST(ModbusConfig, NonFiniteFloatInputsReachTheLoopAsNan) {
  json s = base();
  s["registers"]["position"]["Y"] = {{"address", 2}, {"type", "float32"}, {"counts_per_mm", 1}};
  const modbus::ModbusSettings c = parseModbusSettings(s, "plant.json", "transport");
  std::array<std::uint16_t, 32> holding{};
  std::array<std::uint16_t, 1> input{};
  holding[1] = 12345;   // X low word: 1.2345 mm
  holding[2] = 0x7FC0;  // Y: a quiet NaN
  holding[6] = 0b11;    // enable, homed
  loop::AxisSample out;
  ASSERT_FALSE(modbus::decodeInputs(c.registers, modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_NEAR(out.positionMm[0], 1.2345, 1e-12);
  EXPECT_TRUE(std::isnan(out.positionMm[1]));
  EXPECT_TRUE(out.enable && out.homed);
  holding[2] = 0x7F80;  // Y: +infinity
  ASSERT_FALSE(modbus::decodeInputs(c.registers, modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_TRUE(std::isnan(out.positionMm[1]));
}

// The fault-acknowledge input: a bit, possibly in the enable/homed register (on its own bit),
// decoded into the sample and encoded by the simulated controller.
TEST(ModbusConfig, FaultAckBitSharesTheFlagRegisterOnItsOwnBit) {
  json s = base();
  s["registers"]["fault_ack"] = {{"address", 6}, {"bit", 2}};
  const modbus::ModbusSettings c = parseModbusSettings(s, "plant.json", "transport");
  ASSERT_TRUE(c.registers.faultAck.has_value());
  EXPECT_EQ(c.registers.faultAck->bit, 2);
  std::array<std::uint16_t, 32> holding{};
  std::array<std::uint16_t, 1> input{};
  loop::AxisSample in;
  in.enable = true;
  in.faultAck = true;
  ASSERT_FALSE(modbus::encodeInputs(c.registers, in, modbus::TableView{holding, 0},
                                    modbus::TableView{input, 0}));
  EXPECT_EQ(holding[6], 0b101);
  loop::AxisSample out;
  ASSERT_FALSE(modbus::decodeInputs(c.registers, modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_TRUE(out.hasFaultAck);
  EXPECT_TRUE(out.faultAck);
  EXPECT_TRUE(out.enable);
  EXPECT_FALSE(out.homed);
  // Unmapped: the sample says so.
  ASSERT_FALSE(modbus::decodeInputs(parseModbusSettings(base(), "p.json", "t").registers,
                                    modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_FALSE(out.hasFaultAck);
  EXPECT_FALSE(out.faultAck);
  s["registers"]["fault_ack"]["bit"] = 1;  // homed's bit
  expectRejected(s, "transport.registers.fault_ack.bit", "homed and fault_ack use the same bit");
}

// The timestamp register: when the controller latched the positions, uint16 ticks of tick_us,
// read with the other inputs into the sample (tick in seconds) and written by the simulator.
TEST(ModbusConfig, TimestampRegisterIsReadWithTheInputs) {
  json s = base();
  s["registers"]["timestamp"] = {{"address", 22}, {"tick_us", 10}};
  const modbus::ModbusSettings c = parseModbusSettings(s, "plant.json", "transport");
  ASSERT_TRUE(c.registers.timestamp.has_value());
  EXPECT_EQ(c.registers.timestamp->address, 22);
  EXPECT_EQ(c.registers.timestamp->table, RegisterTable::Holding);
  EXPECT_DOUBLE_EQ(c.registers.timestamp->tickUs, 10.0);
  // One FC03 still: the inputs now span 0..22.
  const modbus::RegisterPlan plan = modbus::planRegisters(c.registers);
  EXPECT_EQ(plan.holdingRead.start, 0);
  EXPECT_EQ(plan.holdingRead.count, 23);
  std::array<std::uint16_t, 32> holding{};
  std::array<std::uint16_t, 1> input{};
  loop::AxisSample in;
  in.timestampTicks = 54321;
  ASSERT_FALSE(modbus::encodeInputs(c.registers, in, modbus::TableView{holding, 0},
                                    modbus::TableView{input, 0}));
  EXPECT_EQ(holding[22], 54321);
  loop::AxisSample out;
  ASSERT_FALSE(modbus::decodeInputs(c.registers, modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_TRUE(out.hasTimestamp);
  EXPECT_EQ(out.timestampTicks, 54321);
  EXPECT_DOUBLE_EQ(out.timestampTickS, 10e-6);
  ASSERT_FALSE(modbus::decodeInputs(parseModbusSettings(base(), "p.json", "t").registers,
                                    modbus::ConstTableView{holding, 0},
                                    modbus::ConstTableView{input, 0}, out));
  EXPECT_FALSE(out.hasTimestamp);

  s["registers"]["timestamp"]["tick_us"] = 0;
  expectRejected(s, "transport.registers.timestamp.tick_us", "0.1");
  s["registers"]["timestamp"].erase("tick_us");
  expectRejected(s, "transport.registers.timestamp.tick_us", "");
  s["registers"]["timestamp"] = {{"address", 7}, {"tick_us", 1}};  // the sequence register
  expectRejected(s, "transport.registers.timestamp", "overlaps sequence");
}

TEST(ModbusConfig, RejectsUnknownKeysAndBadValues) {
  json s = base();
  s["registers"]["offsets"] = s["registers"]["offset"];
  expectRejected(s, "transport.registers.offsets", "unknown key");

  s = base();
  s["registers"]["position"]["Y"]["sign"] = 0;
  expectRejected(s, "transport.registers.position.Y.sign", "+1 or -1");

  s = base();
  s["registers"]["defaults"]["counts_per_mm"] = 0;
  expectRejected(s, "transport.registers.defaults.counts_per_mm", "positive");

  s = base();
  s["registers"]["position"]["Z"]["type"] = "int24";
  expectRejected(s, "transport.registers.position.Z.type", "int16");

  s = base();
  s["registers"]["offset"]["X"]["order"] = "ABDC";
  expectRejected(s, "transport.registers.offset.X.order", "CDAB");

  s = base();
  s["registers"]["enable"]["bit"] = 16;
  expectRejected(s, "transport.registers.enable.bit", "");

  s = base();
  s["port"] = 70000;
  expectRejected(s, "transport.port", "");

  s = test::rtuTransportJson("/dev/ttyS0");
  s["slave_id"] = 0;
  expectRejected(s, "transport.slave_id", "");

  s = test::rtuTransportJson("/dev/ttyS0");
  s["parity"] = "M";
  expectRejected(s, "transport.parity", "");

  s = base();
  s["type"] = "modbus-udp";
  expectRejected(s, "transport.type", "modbus-tcp");

  s = base();
  s.erase("registers");
  expectRejected(s, "transport.registers", "missing");
}

TEST(ModbusConfig, RejectsOverlaps) {
  json s = base();
  s["registers"]["position"]["Y"]["address"] = 1;  // X is 0..1
  expectRejected(s, "transport.registers.position.Y", "overlaps position.X");

  s = base();
  s["registers"]["sequence"]["address"] = 5;  // Z is 4..5
  expectRejected(s, "transport.registers.sequence", "overlaps position.Z");

  s = base();
  s["registers"]["homed"]["bit"] = 0;  // enable is bit 0 of the same register
  expectRejected(s, "transport.registers.homed.bit", "enable and homed use the same bit");

  s = base();
  s["registers"]["status"] = 19;  // offset Z is 18..19
  expectRejected(s, "transport.registers.status", "overlaps offset.Z");

  // Applied offset overlapping another axis' output is not a read-back.
  s = base();
  s["registers"]["applied_offset"]["X"]["address"] = 16;
  expectRejected(s, "transport.registers.offset.Y", "overlaps applied_offset.X");
}

TEST(ModbusConfig, OutputsMustBeOneGapFreeHoldingBlock) {
  json s = base();
  s["registers"]["heartbeat"] = 30;
  expectRejected(s, "transport.registers", "gap-free");

  s = base();
  s["registers"]["offset"]["Y"]["table"] = "input";
  expectRejected(s, "transport.registers.offset.Y", "holding");
}

TEST(ModbusConfig, ReadAndWriteSpansFitOneTransaction) {
  json s = base();
  s["registers"]["sequence"]["address"] = 200;  // holding inputs 0..200: 201 registers
  expectRejected(s, "transport.registers", "at most 125");

  // 125 registers exactly is fine: inputs 0..124.
  s["registers"]["sequence"]["address"] = 124;
  EXPECT_NO_THROW(parseModbusSettings(s, "plant.json", "transport"));
}

TEST(ModbusConfig, AddressesEndWithinTheTable) {
  json s = base();
  s["registers"]["position"]["X"] = {{"address", 65534}, {"table", "input"}, {"type", "float64"}};
  expectRejected(s, "transport.registers.position.X", "past address 65535");

  s = base();
  s["registers"]["position"]["X"]["address"] = 65536;
  expectRejected(s, "transport.registers.position.X.address", "");
}

TEST(ModbusConfig, Fc23NeedsHoldingInputs) {
  json s = test::tcpTransportJson(1502, true);
  EXPECT_TRUE(parseModbusSettings(s, "plant.json", "transport").registers.fc23);
  s["registers"]["position"]["X"]["table"] = "input";
  s["registers"]["position"]["X"]["address"] = 0;
  expectRejected(s, "transport.registers.position.X", "fc23");
}

}  // namespace
}  // namespace volcomp::config
