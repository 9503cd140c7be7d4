// Modbus replies as the daemon decodes them: the register words a read returned, through the
// codec (drivers/modbus: one typed value in any type, word order, scale and sign) and through a
// whole register map (decodeInputs, what the loop gets, and describeInputs, what --probe shows).
// The maps are those of the example configurations and maps built from the input that
// config::validateModbusRegisterMap accepts. The first byte chooses; the words follow.
// A value the codec calls Ok is finite; an integer value encodes back to the words it came from.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "fuzz_support.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/modbus_config.hpp"
#include "volcomp/modbus/codec.hpp"
#include "volcomp/modbus/register_plan.hpp"

namespace {

using namespace volcomp;
using modbus::CodecStatus;
using modbus::RegisterType;

/// Scales as configurations give them, extremes included (any positive number is accepted).
constexpr std::array<double, 8> kCountsPerMm{1.0, 1000.0, 10000.0, 1e6, 0.001, 3.0, 1e-300, 1e300};

modbus::ValueFormat takeFormat(fuzz::ByteReader& in) {
  const auto bits = in.take<std::uint8_t>();
  modbus::ValueFormat f;
  f.type = static_cast<RegisterType>(bits % 6);
  f.order = static_cast<modbus::WordOrder>((bits / 6) % 4);
  f.sign = (bits & 0x80) != 0 ? -1 : 1;
  f.countsPerMm = kCountsPerMm[in.take<std::uint8_t>() % kCountsPerMm.size()];
  return f;
}

bool isInteger(RegisterType t) {
  return t != RegisterType::Float32 && t != RegisterType::Float64;
}

void checkValue(std::span<const std::uint16_t> words, const modbus::ValueFormat& format) {
  double mm = 0.0;
  const CodecStatus status = modbus::decode(words, format, mm);
  fuzz::require(status != CodecStatus::Saturated, "decode reported saturation");
  if (status == CodecStatus::NotFinite) {
    fuzz::require(std::isnan(mm), "a value that is not a number is not NaN");
    return;
  }
  fuzz::require(std::isfinite(mm), "decode said Ok for a value that is not finite");
  std::array<std::uint16_t, 4> again{};
  const CodecStatus back = modbus::encode(mm, format, again);
  if (isInteger(format.type) && back == CodecStatus::Ok) {
    const auto width = static_cast<std::size_t>(modbus::registerWidth(format.type));
    for (std::size_t i = 0; i < width; ++i)
      fuzz::require(again[i] == words[i], "an integer value does not encode to its words");
  }
}

const std::vector<modbus::RegisterMap>& exampleMaps() {
  static const std::vector<modbus::RegisterMap> maps = [] {
    std::vector<modbus::RegisterMap> out;
    for (const char* name : {"volcompd-modbus-tcp.json", "volcompd-modbus-rtu.json"}) {
      const config::DaemonConfig c = config::loadDaemonConfig(VOLCOMP_EXAMPLES_DIR + "/" + name);
      out.push_back(std::get<modbus::ModbusSettings>(c.transport).registers);
    }
    return out;
  }();
  return maps;
}

/// A map from the input, or none when validation refuses it.
bool takeMap(fuzz::ByteReader& in, modbus::RegisterMap& m) {
  auto value = [&](modbus::ValueRegister& v) {
    v.table = (in.take<std::uint8_t>() & 1) != 0 ? modbus::RegisterTable::Input
                                                 : modbus::RegisterTable::Holding;
    v.address = in.take<std::uint16_t>();
    v.format = takeFormat(in);
  };
  auto bit = [&](modbus::BitRegister& b) {
    const auto bits = in.take<std::uint8_t>();
    b.table = (bits & 0x10) != 0 ? modbus::RegisterTable::Input : modbus::RegisterTable::Holding;
    b.bit = bits & 0x0F;
    b.address = in.take<std::uint16_t>();
  };
  const auto flags = in.take<std::uint8_t>();
  for (auto& p : m.position) value(p);
  bit(m.enable);
  bit(m.homed);
  if ((flags & 1) != 0) bit(m.faultAck.emplace());
  if ((flags & 2) != 0) {
    auto& s = m.sequence.emplace();
    s.table = (flags & 4) != 0 ? modbus::RegisterTable::Input : modbus::RegisterTable::Holding;
    s.address = in.take<std::uint16_t>();
  }
  if ((flags & 8) != 0) {
    for (auto& a : m.appliedOffset.emplace()) value(a);
  }
  for (auto& o : m.offset) value(o);
  m.statusAddress = in.take<std::uint16_t>();
  m.heartbeatAddress = in.take<std::uint16_t>();
  m.fc23 = (flags & 16) != 0;
  try {
    config::validateModbusRegisterMap(m, "fuzz.json", "transport.registers");
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
    return false;
  }
  return true;
}

void checkMap(const modbus::RegisterMap& map, fuzz::ByteReader& in) {
  const modbus::RegisterPlan plan = modbus::planRegisters(map);
  fuzz::require(plan.holdingRead.count <= modbus::kMaxReadRegisters &&
                    plan.inputRead.count <= modbus::kMaxReadRegisters,
                "a read block longer than one transaction");
  // The words of the reply, as libmodbus hands them over: exactly the blocks asked for.
  std::vector<std::uint16_t> holding(plan.holdingRead.count), input(plan.inputRead.count);
  for (std::uint16_t& w : holding) w = in.take<std::uint16_t>();
  for (std::uint16_t& w : input) w = in.take<std::uint16_t>();
  const modbus::ConstTableView h{holding, plan.holdingRead.start};
  const modbus::ConstTableView i{input, plan.inputRead.start};
  loop::AxisSample sample;
  // Never fails: a non-finite input reaches the loop as NaN (an invalid-input fault there).
  fuzz::require(!modbus::decodeInputs(map, h, i, sample), "decoding the inputs failed");
  const auto finiteOrNan = [](double v) { return std::isfinite(v) || std::isnan(v); };
  for (const double p : sample.positionMm) fuzz::require(finiteOrNan(p), "position infinite");
  if (sample.hasAppliedOffsets) {
    for (const double a : sample.appliedOffsetMm)
      fuzz::require(finiteOrNan(a), "applied offset infinite");
  }
  const modbus::FieldReadings readings = modbus::describeInputs(map, h, i);
  fuzz::require(readings.count <= modbus::kMaxFieldReadings, "too many readings");
  for (std::size_t k = 0; k < readings.count; ++k) {
    const modbus::FieldReading& r = readings.fields[k];
    if (r.isValue && r.status == CodecStatus::Ok)
      fuzz::require(std::isfinite(r.valueMm), "a reading called Ok is not finite");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::ByteReader in(data, size);
  switch (in.take<std::uint8_t>() % 3) {
    case 0: {
      const modbus::ValueFormat format = takeFormat(in);
      std::array<std::uint16_t, 4> words{};
      for (std::uint16_t& w : words) w = in.take<std::uint16_t>();
      checkValue(words, format);
      break;
    }
    case 1: {
      const auto& maps = exampleMaps();
      checkMap(maps[in.take<std::uint8_t>() % maps.size()], in);
      break;
    }
    default: {
      modbus::RegisterMap map;
      if (takeMap(in, map)) checkMap(map, in);
      break;
    }
  }
  return 0;
}
