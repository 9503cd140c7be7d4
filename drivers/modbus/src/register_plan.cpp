#include "volcomp/modbus/register_plan.hpp"

#include <algorithm>

#include "volcomp/modbus/codec.hpp"
#include "volcomp/modbus/error.hpp"

namespace volcomp::modbus {
namespace {

struct Span {
  int lo = 65536;
  int hi = -1;
  void add(int start, int width) noexcept {
    lo = std::min(lo, start);
    hi = std::max(hi, start + width - 1);
  }
  Block block() const noexcept {
    if (hi < 0) return {};
    return {static_cast<std::uint16_t>(lo), static_cast<std::uint16_t>(hi - lo + 1)};
  }
};

std::span<const std::uint16_t> at(ConstTableView v, std::uint16_t address, int width) noexcept {
  return v.registers.subspan(static_cast<std::size_t>(address - v.base),
                             static_cast<std::size_t>(width));
}
std::span<std::uint16_t> at(TableView v, std::uint16_t address, int width) noexcept {
  return v.registers.subspan(static_cast<std::size_t>(address - v.base),
                             static_cast<std::size_t>(width));
}

template <typename View>
View pick(RegisterTable t, View holding, View input) noexcept {
  return t == RegisterTable::Input ? input : holding;
}

std::error_code toError(CodecStatus s) noexcept {
  switch (s) {
    case CodecStatus::Ok:
      return {};
    case CodecStatus::Saturated:
      return Errc::value_out_of_range;
    case CodecStatus::NotFinite:
      return Errc::value_not_finite;
  }
  return Errc::value_out_of_range;
}

}  // namespace

RegisterPlan planRegisters(const RegisterMap& m) noexcept {
  Span holding, input, write;
  auto addInput = [&](RegisterTable t, int start, int width) {
    (t == RegisterTable::Input ? input : holding).add(start, width);
  };
  for (const auto& p : m.position) addInput(p.table, p.address, registerWidth(p.format.type));
  addInput(m.enable.table, m.enable.address, 1);
  addInput(m.homed.table, m.homed.address, 1);
  if (m.faultAck) addInput(m.faultAck->table, m.faultAck->address, 1);
  if (m.sequence) addInput(m.sequence->table, m.sequence->address, 1);
  if (m.timestamp) addInput(m.timestamp->table, m.timestamp->address, 1);
  if (m.appliedOffset) {
    for (const auto& a : *m.appliedOffset) {
      addInput(a.table, a.address, registerWidth(a.format.type));
    }
  }
  for (const auto& o : m.offset) write.add(o.address, registerWidth(o.format.type));
  write.add(m.statusAddress, 1);
  write.add(m.heartbeatAddress, 1);
  return {holding.block(), input.block(), write.block()};
}

// A NaN or infinity from the controller is its data, not a failed transaction: it reaches the
// loop as NaN, which faults it as invalid input (latched), never as a transport error.
std::error_code decodeInputs(const RegisterMap& m, ConstTableView holding, ConstTableView input,
                             loop::AxisSample& out) noexcept {
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& p = m.position[i];
    const auto regs = at(pick(p.table, holding, input), p.address, registerWidth(p.format.type));
    decode(regs, p.format, out.positionMm[i]);
  }
  auto bit = [&](const BitRegister& b) {
    return ((at(pick(b.table, holding, input), b.address, 1)[0] >> b.bit) & 1U) != 0;
  };
  out.enable = bit(m.enable);
  out.homed = bit(m.homed);
  out.hasFaultAck = m.faultAck.has_value();
  out.faultAck = m.faultAck && bit(*m.faultAck);
  out.hasSequence = m.sequence.has_value();
  if (m.sequence)
    out.sequence = at(pick(m.sequence->table, holding, input), m.sequence->address, 1)[0];
  out.hasTimestamp = m.timestamp.has_value();
  if (m.timestamp) {
    out.timestampTicks = at(pick(m.timestamp->table, holding, input), m.timestamp->address, 1)[0];
    out.timestampTickS = m.timestamp->tickUs * 1e-6;
  }
  out.hasAppliedOffsets = m.appliedOffset.has_value();
  if (m.appliedOffset) {
    for (std::size_t i = 0; i < 3; ++i) {
      const auto& a = (*m.appliedOffset)[i];
      const auto regs = at(pick(a.table, holding, input), a.address, registerWidth(a.format.type));
      decode(regs, a.format, out.appliedOffsetMm[i]);
    }
  }
  return {};
}

std::error_code encodeOutputs(const RegisterMap& m, const loop::OffsetCommand& command,
                              TableView holding) noexcept {
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& o = m.offset[i];
    const auto regs = at(holding, o.address, registerWidth(o.format.type));
    if (auto ec = toError(encode(command.offsetMm[i], o.format, regs))) return ec;
  }
  at(holding, m.statusAddress, 1)[0] = command.status;
  at(holding, m.heartbeatAddress, 1)[0] = command.heartbeat;
  return {};
}

std::error_code encodeInputs(const RegisterMap& m, const loop::AxisSample& sample,
                             TableView holding, TableView input) noexcept {
  std::error_code result;
  auto put = [&](const ValueRegister& r, double mm) {
    const auto regs = at(pick(r.table, holding, input), r.address, registerWidth(r.format.type));
    if (auto ec = toError(encode(mm, r.format, regs)); ec && !result) result = ec;
  };
  for (std::size_t i = 0; i < 3; ++i) put(m.position[i], sample.positionMm[i]);
  auto setBit = [&](const BitRegister& b, bool on) {
    auto& reg = at(pick(b.table, holding, input), b.address, 1)[0];
    const auto mask = static_cast<std::uint16_t>(1U << b.bit);
    reg = on ? static_cast<std::uint16_t>(reg | mask) : static_cast<std::uint16_t>(reg & ~mask);
  };
  setBit(m.enable, sample.enable);
  setBit(m.homed, sample.homed);
  if (m.faultAck) setBit(*m.faultAck, sample.faultAck);
  if (m.sequence)
    at(pick(m.sequence->table, holding, input), m.sequence->address, 1)[0] = sample.sequence;
  if (m.timestamp) {
    at(pick(m.timestamp->table, holding, input), m.timestamp->address, 1)[0] =
        sample.timestampTicks;
  }
  if (m.appliedOffset) {
    for (std::size_t i = 0; i < 3; ++i) put((*m.appliedOffset)[i], sample.appliedOffsetMm[i]);
  }
  return result;
}

std::error_code decodeOutputs(const RegisterMap& m, ConstTableView holding,
                              loop::OffsetCommand& out) noexcept {
  std::error_code result;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& o = m.offset[i];
    const auto regs = at(holding, o.address, registerWidth(o.format.type));
    if (auto ec = toError(decode(regs, o.format, out.offsetMm[i])); ec && !result) result = ec;
  }
  out.status = at(holding, m.statusAddress, 1)[0];
  out.heartbeat = at(holding, m.heartbeatAddress, 1)[0];
  return result;
}

namespace {

void copyRegisters(std::span<const std::uint16_t> regs, FieldReading& r) noexcept {
  for (std::size_t i = 0; i < regs.size() && i < r.registers.size(); ++i) r.registers[i] = regs[i];
}

void addValue(FieldReadings& out, const char* name, const ValueRegister& v, ConstTableView holding,
              ConstTableView input) noexcept {
  FieldReading& r = out.fields[out.count++];
  r.name = name;
  r.table = v.table;
  r.address = v.address;
  r.width = registerWidth(v.format.type);
  r.format = v.format;
  r.isValue = true;
  const auto regs = at(pick(v.table, holding, input), v.address, r.width);
  copyRegisters(regs, r);
  r.status = decode(regs, v.format, r.valueMm);
}

void addWord(FieldReadings& out, const char* name, RegisterTable table, std::uint16_t address,
             int bit, ConstTableView holding, ConstTableView input) noexcept {
  FieldReading& r = out.fields[out.count++];
  r.name = name;
  r.table = table;
  r.address = address;
  r.bit = bit;
  r.format.type = RegisterType::Uint16;
  const auto regs = at(pick(table, holding, input), address, 1);
  copyRegisters(regs, r);
  r.word = bit >= 0 ? (regs[0] >> bit) & 1U : regs[0];
}

}  // namespace

FieldReadings describeInputs(const RegisterMap& m, ConstTableView holding,
                             ConstTableView input) noexcept {
  static constexpr const char* kPosition[] = {"position.X", "position.Y", "position.Z"};
  static constexpr const char* kApplied[] = {"applied_offset.X", "applied_offset.Y",
                                             "applied_offset.Z"};
  FieldReadings out;
  for (std::size_t i = 0; i < 3; ++i) addValue(out, kPosition[i], m.position[i], holding, input);
  addWord(out, "enable", m.enable.table, m.enable.address, m.enable.bit, holding, input);
  addWord(out, "homed", m.homed.table, m.homed.address, m.homed.bit, holding, input);
  if (m.sequence) {
    addWord(out, "sequence", m.sequence->table, m.sequence->address, -1, holding, input);
  }
  if (m.timestamp) {
    addWord(out, "timestamp", m.timestamp->table, m.timestamp->address, -1, holding, input);
  }
  if (m.appliedOffset) {
    for (std::size_t i = 0; i < 3; ++i)
      addValue(out, kApplied[i], (*m.appliedOffset)[i], holding, input);
  }
  return out;
}

FieldReadings describeOutputs(const RegisterMap& m, ConstTableView holding) noexcept {
  static constexpr const char* kOffset[] = {"offset.X", "offset.Y", "offset.Z"};
  FieldReadings out;
  for (std::size_t i = 0; i < 3; ++i) addValue(out, kOffset[i], m.offset[i], holding, holding);
  addWord(out, "status", RegisterTable::Holding, m.statusAddress, -1, holding, holding);
  addWord(out, "heartbeat", RegisterTable::Holding, m.heartbeatAddress, -1, holding, holding);
  return out;
}

}  // namespace volcomp::modbus
