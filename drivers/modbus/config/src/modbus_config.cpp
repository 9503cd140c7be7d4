#include "volcomp/config/modbus_config.hpp"

#include <algorithm>
#include <string_view>
#include <vector>

#include <arpa/inet.h>

#include "volcomp/config/json_reader.hpp"

namespace volcomp::config {
namespace {

using modbus::BitRegister;
using modbus::ModbusSettings;
using modbus::RegisterMap;
using modbus::RegisterTable;
using modbus::RegisterType;
using modbus::TimestampRegister;
using modbus::ValueFormat;
using modbus::ValueRegister;
using modbus::WordOrder;
using modbus::WordRegister;

constexpr std::array<const char*, 3> kAxisNames{"X", "Y", "Z"};

RegisterTable parseTable(const JsonReader& r) {
  return r.oneOf({"holding", "input"}) == "input" ? RegisterTable::Input : RegisterTable::Holding;
}

RegisterType parseType(const JsonReader& r) {
  const std::string t = r.oneOf({"int16", "uint16", "int32", "uint32", "float32", "float64"});
  if (t == "int16") return RegisterType::Int16;
  if (t == "uint16") return RegisterType::Uint16;
  if (t == "int32") return RegisterType::Int32;
  if (t == "uint32") return RegisterType::Uint32;
  if (t == "float32") return RegisterType::Float32;
  return RegisterType::Float64;
}

WordOrder parseOrder(const JsonReader& r) {
  const std::string o = r.oneOf({"ABCD", "CDAB", "BADC", "DCBA"});
  if (o == "CDAB") return WordOrder::CDAB;
  if (o == "BADC") return WordOrder::BADC;
  if (o == "DCBA") return WordOrder::DCBA;
  return WordOrder::ABCD;
}

int parseSign(const JsonReader& r) {
  const auto s = r.integer(-1, 1);
  if (s == 0) r.failExpected("+1 or -1");
  return static_cast<int>(s);
}

double parseScale(const JsonReader& r) {
  const double s = r.number();
  if (!(s > 0.0)) r.failExpected("a positive number of counts per mm");
  return s;
}

std::uint16_t parseAddress(const JsonReader& r) {
  return static_cast<std::uint16_t>(r.integer(0, 65535));
}

/// Defaults for value registers ("registers.defaults").
struct ValueDefaults {
  RegisterTable table = RegisterTable::Holding;
  ValueFormat format;
};

ValueDefaults parseDefaults(const JsonReader& registers) {
  ValueDefaults d;
  const auto defaults = registers.find("defaults");
  if (!defaults) return d;
  defaults->allowOnly({"table", "type", "order", "counts_per_mm", "sign"});
  if (auto v = defaults->find("table")) d.table = parseTable(*v);
  if (auto v = defaults->find("type")) d.format.type = parseType(*v);
  if (auto v = defaults->find("order")) d.format.order = parseOrder(*v);
  if (auto v = defaults->find("counts_per_mm")) d.format.countsPerMm = parseScale(*v);
  if (auto v = defaults->find("sign")) d.format.sign = parseSign(*v);
  return d;
}

ValueRegister parseValue(const JsonReader& r, const ValueDefaults& d) {
  r.allowOnly({"address", "table", "type", "order", "counts_per_mm", "sign"});
  ValueRegister v;
  v.table = d.table;
  v.format = d.format;
  v.address = parseAddress(r.at("address"));
  if (auto x = r.find("table")) v.table = parseTable(*x);
  if (auto x = r.find("type")) v.format.type = parseType(*x);
  if (auto x = r.find("order")) v.format.order = parseOrder(*x);
  if (auto x = r.find("counts_per_mm")) v.format.countsPerMm = parseScale(*x);
  if (auto x = r.find("sign")) v.format.sign = parseSign(*x);
  return v;
}

std::array<ValueRegister, 3> parseAxes(const JsonReader& r, const ValueDefaults& d) {
  r.allowOnly({"X", "Y", "Z"});
  std::array<ValueRegister, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) out[i] = parseValue(r.at(kAxisNames[i]), d);
  return out;
}

BitRegister parseBit(const JsonReader& r) {
  r.allowOnly({"address", "bit", "table"});
  BitRegister b;
  b.address = parseAddress(r.at("address"));
  b.bit = static_cast<std::uint8_t>(r.at("bit").integer(0, 15));
  if (auto t = r.find("table")) b.table = parseTable(*t);
  return b;
}

TimestampRegister parseTimestamp(const JsonReader& r) {
  r.allowOnly({"address", "table", "tick_us"});
  TimestampRegister t;
  t.address = parseAddress(r.at("address"));
  if (auto table = r.find("table")) t.table = parseTable(*table);
  // 0.1 us .. 1 ms: a wrap (2^16 ticks) then spans 6.5 ms .. 65 s, and one tick resolves the
  // positions' age far below a cycle.
  t.tickUs = r.at("tick_us").number(0.1, 1000.0);
  return t;
}

WordRegister parseWord(const JsonReader& r) {
  r.allowOnly({"address", "table"});
  WordRegister w;
  w.address = parseAddress(r.at("address"));
  if (auto t = r.find("table")) w.table = parseTable(*t);
  return w;
}

// Layout validation -------------------------------------------------------------------------------

enum class FieldKind { Position, Flag, Sequence, Applied, Output };

struct Field {
  std::string name;  // key path relative to "registers"
  FieldKind kind;
  RegisterTable table;
  int start;
  int width;
  int axis = -1;
  int bit = -1;  // Flag: the bit it uses
  const char* tableName() const { return table == RegisterTable::Input ? "input" : "holding"; }
};

std::vector<Field> collectFields(const RegisterMap& m) {
  std::vector<Field> f;
  for (int i = 0; i < 3; ++i) {
    const auto& p = m.position[i];
    f.push_back({std::string("position.") + kAxisNames[i], FieldKind::Position, p.table, p.address,
                 modbus::registerWidth(p.format.type), i});
  }
  f.push_back({"enable", FieldKind::Flag, m.enable.table, m.enable.address, 1, -1, m.enable.bit});
  f.push_back({"homed", FieldKind::Flag, m.homed.table, m.homed.address, 1, -1, m.homed.bit});
  if (m.faultAck) {
    f.push_back({"fault_ack", FieldKind::Flag, m.faultAck->table, m.faultAck->address, 1, -1,
                 m.faultAck->bit});
  }
  if (m.sequence)
    f.push_back({"sequence", FieldKind::Sequence, m.sequence->table, m.sequence->address, 1});
  if (m.timestamp)
    f.push_back({"timestamp", FieldKind::Sequence, m.timestamp->table, m.timestamp->address, 1});
  if (m.appliedOffset) {
    for (int i = 0; i < 3; ++i) {
      const auto& a = (*m.appliedOffset)[i];
      f.push_back({std::string("applied_offset.") + kAxisNames[i], FieldKind::Applied, a.table,
                   a.address, modbus::registerWidth(a.format.type), i});
    }
  }
  for (int i = 0; i < 3; ++i) {
    const auto& o = m.offset[i];
    f.push_back({std::string("offset.") + kAxisNames[i], FieldKind::Output, o.table, o.address,
                 modbus::registerWidth(o.format.type), i});
  }
  f.push_back({"status", FieldKind::Output, RegisterTable::Holding, m.statusAddress, 1});
  f.push_back({"heartbeat", FieldKind::Output, RegisterTable::Holding, m.heartbeatAddress, 1});
  return f;
}

std::string joinPath(const std::string& base, const std::string& rel) {
  return base.empty() ? rel : base + "." + rel;
}

bool overlapAllowed(const Field& a, const Field& b, const RegisterMap& m) {
  // Flags may share a register, each on its own bit (checked separately, with its own message).
  if (a.kind == FieldKind::Flag && b.kind == FieldKind::Flag) return true;
  const bool appliedVsOutput = (a.kind == FieldKind::Applied && b.kind == FieldKind::Output) ||
                               (a.kind == FieldKind::Output && b.kind == FieldKind::Applied);
  if (appliedVsOutput && a.axis >= 0 && a.axis == b.axis) {
    const auto& ap = (*m.appliedOffset)[a.axis];
    const auto& of = m.offset[a.axis];
    return ap.table == of.table && ap.address == of.address && ap.format.type == of.format.type &&
           ap.format.order == of.format.order;
  }
  return false;
}

}  // namespace

void validateModbusRegisterMap(const RegisterMap& m, const std::string& file,
                               const std::string& keyPath) {
  const std::vector<Field> fields = collectFields(m);
  for (const Field& f : fields) {
    if (f.start + f.width - 1 > 65535) {
      throw ConfigError(file, joinPath(keyPath, f.name),
                        "field of " + std::to_string(f.width) + " registers at address " +
                            std::to_string(f.start) + " runs past address 65535");
    }
    if (f.kind == FieldKind::Output && f.table != RegisterTable::Holding) {
      throw ConfigError(file, joinPath(keyPath, f.name),
                        "outputs must be holding registers (input registers are read-only)");
    }
    if (m.fc23 && f.kind != FieldKind::Output && f.table != RegisterTable::Holding) {
      throw ConfigError(file, joinPath(keyPath, f.name),
                        "with fc23 every input must be a holding register (FC23 reads holding "
                        "registers only)");
    }
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    for (std::size_t j = i + 1; j < fields.size(); ++j) {
      const Field& a = fields[i];
      const Field& b = fields[j];
      if (a.kind == FieldKind::Flag && b.kind == FieldKind::Flag && a.table == b.table &&
          a.start == b.start && a.bit == b.bit) {
        throw ConfigError(file, joinPath(keyPath, b.name + ".bit"),
                          a.name + " and " + b.name + " use the same bit of the same register");
      }
    }
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    for (std::size_t j = i + 1; j < fields.size(); ++j) {
      const Field& a = fields[i];
      const Field& b = fields[j];
      if (a.table != b.table) continue;
      const bool overlap = a.start < b.start + b.width && b.start < a.start + a.width;
      if (overlap && !overlapAllowed(a, b, m)) {
        throw ConfigError(file, joinPath(keyPath, b.name),
                          std::string("overlaps ") + a.name + " (" + a.tableName() + " registers " +
                              std::to_string(a.start) + ".." +
                              std::to_string(a.start + a.width - 1) + ")");
      }
    }
  }
  // Outputs: one gap-free block, so that one FC16 (or FC23) writes all of them.
  int lo = 65536, hi = -1, total = 0;
  for (const Field& f : fields) {
    if (f.kind != FieldKind::Output) continue;
    lo = std::min(lo, f.start);
    hi = std::max(hi, f.start + f.width - 1);
    total += f.width;
  }
  const int span = hi - lo + 1;
  if (span != total) {
    throw ConfigError(file, keyPath,
                      "the outputs (offset.X/Y/Z, status, heartbeat) must fill one gap-free block "
                      "of holding registers so that one transaction writes them all; they span " +
                          std::to_string(lo) + ".." + std::to_string(hi) + " (" +
                          std::to_string(span) + " registers) but occupy " + std::to_string(total));
  }
  const int maxWrite = m.fc23 ? modbus::kMaxFc23WriteRegisters : modbus::kMaxWriteRegisters;
  if (span > maxWrite) {
    throw ConfigError(file, keyPath,
                      "the output block has " + std::to_string(span) +
                          " registers; one write carries at most " + std::to_string(maxWrite));
  }
  for (RegisterTable t : {RegisterTable::Holding, RegisterTable::Input}) {
    int ilo = 65536, ihi = -1;
    std::string first, last;
    for (const Field& f : fields) {
      if (f.kind == FieldKind::Output || f.table != t) continue;
      if (f.start < ilo) {
        ilo = f.start;
        first = f.name;
      }
      if (f.start + f.width - 1 > ihi) {
        ihi = f.start + f.width - 1;
        last = f.name;
      }
    }
    if (ihi >= 0 && ihi - ilo + 1 > modbus::kMaxReadRegisters) {
      throw ConfigError(
          file, keyPath,
          std::string("the ") + (t == RegisterTable::Input ? "input" : "holding") +
              "-register inputs span " + std::to_string(ihi - ilo + 1) + " registers (" + first +
              " .. " + last + "); one read carries at most " +
              std::to_string(modbus::kMaxReadRegisters) + ": place them closer together");
    }
  }
}

RegisterMap parseModbusRegisterMap(const nlohmann::json& registers, const std::string& file,
                                   const std::string& keyPath) {
  const JsonReader r(registers, file, keyPath);
  r.allowOnly({"fc23", "defaults", "position", "enable", "homed", "fault_ack", "sequence",
               "timestamp", "applied_offset", "offset", "status", "heartbeat"});
  const ValueDefaults d = parseDefaults(r);
  RegisterMap m;
  m.fc23 = r.booleanOr("fc23", false);
  m.position = parseAxes(r.at("position"), d);
  m.enable = parseBit(r.at("enable"));
  m.homed = parseBit(r.at("homed"));
  if (auto a = r.find("fault_ack")) m.faultAck = parseBit(*a);
  if (auto s = r.find("sequence")) m.sequence = parseWord(*s);
  if (auto t = r.find("timestamp")) m.timestamp = parseTimestamp(*t);
  if (auto a = r.find("applied_offset")) m.appliedOffset = parseAxes(*a, d);
  m.offset = parseAxes(r.at("offset"), d);
  m.statusAddress = parseAddress(r.at("status"));
  m.heartbeatAddress = parseAddress(r.at("heartbeat"));
  validateModbusRegisterMap(m, file, keyPath);
  return m;
}

namespace {

// The server role: the master writes every input, so each must be a holding register (input
// registers are read-only on the wire), and an applied-offset read-back must be registers the
// master writes, not the offset outputs the server itself fills.
void validateServerMap(const RegisterMap& m, const std::string& file, const std::string& keyPath) {
  const auto holding = [&](RegisterTable table, const std::string& name) {
    if (table != RegisterTable::Holding) {
      throw ConfigError(file, joinPath(keyPath, name + ".table"),
                        "with role \"server\" the master writes every input, so it must be a "
                        "holding register (input registers are read-only for a master)");
    }
  };
  for (std::size_t k = 0; k < 3; ++k) {
    holding(m.position[k].table, std::string("position.") + kAxisNames[k]);
  }
  holding(m.enable.table, "enable");
  holding(m.homed.table, "homed");
  if (m.faultAck) holding(m.faultAck->table, "fault_ack");
  if (m.sequence) holding(m.sequence->table, "sequence");
  if (m.timestamp) holding(m.timestamp->table, "timestamp");
  if (m.appliedOffset) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::string name = std::string("applied_offset.") + kAxisNames[k];
      holding((*m.appliedOffset)[k].table, name);
      if ((*m.appliedOffset)[k].address == m.offset[k].address) {
        throw ConfigError(file, joinPath(keyPath, name),
                          "with role \"server\" the applied offsets are registers the master "
                          "writes, not the offset outputs it reads");
      }
    }
  }
}

std::uint32_t parseIpv4(const JsonReader& r) {
  const std::string text = r.string();
  in_addr addr{};
  if (inet_pton(AF_INET, text.c_str(), &addr) != 1) {
    r.failExpected("an IPv4 address in dotted form (e.g. \"192.168.0.20\")");
  }
  return addr.s_addr;
}

modbus::ServerSettings parseServer(const JsonReader& r, bool tcp) {
  modbus::ServerSettings s;
  if (auto t = r.find("cycle_trigger")) {
    s.trigger = t->oneOf({"write", "timer"}) == "timer" ? modbus::CycleTrigger::Timer
                                                        : modbus::CycleTrigger::Write;
  }
  if (!tcp) return s;
  if (auto a = r.find("listen_address")) {
    parseIpv4(*a);
    s.listenAddress = a->string();
  }
  if (auto list = r.find("allowed_clients")) {
    for (const JsonReader& a : list->elements(1, 64)) s.allowedClients.push_back(parseIpv4(a));
  }
  s.maxConnections = static_cast<int>(r.integerOr("max_connections", 1, 64, 1));
  s.idleTimeoutS = static_cast<int>(r.integerOr("idle_timeout_s", 0, 86400, 60));
  s.keepaliveS = static_cast<int>(r.integerOr("keepalive_s", 0, 3600, 10));
  s.takeoverAfterMs = static_cast<int>(r.integerOr("takeover_after_ms", 10, 3600000, 1000));
  return s;
}

}  // namespace

ModbusSettings parseModbusSettings(const nlohmann::json& section, const std::string& file,
                                   const std::string& keyPath) {
  const JsonReader r(section, file, keyPath);
  r.expectObject();
  const std::string type = r.at("type").oneOf({"modbus-tcp", "modbus-rtu"});
  ModbusSettings c;
  if (auto role = r.find("role")) {
    c.role = role->oneOf({"client", "server"}) == "server" ? modbus::ModbusRole::Server
                                                           : modbus::ModbusRole::Client;
  }
  const bool server = c.role == modbus::ModbusRole::Server;
  if (type == "modbus-tcp") {
    if (server) {
      r.allowOnly({"type", "role", "port", "listen_address", "allowed_clients", "max_connections",
                   "idle_timeout_s", "keepalive_s", "takeover_after_ms", "cycle_trigger",
                   "slave_id", "response_timeout_ms", "registers"});
    } else {
      r.allowOnly({"type", "role", "host", "port", "slave_id", "response_timeout_ms",
                   "link_loss_timeouts", "registers"});
    }
    modbus::TcpLink tcp;
    if (!server) {
      tcp.host = r.at("host").string();
      if (tcp.host.empty()) r.at("host").failExpected("a host name or address");
    }
    // A server may listen on any free port (0: chosen at start and logged).
    tcp.port = static_cast<std::uint16_t>(r.at("port").integer(server ? 0 : 1, 65535));
    c.link = tcp;
  } else {
    if (server) {
      r.allowOnly({"type", "role", "device", "baud", "parity", "data_bits", "stop_bits",
                   "cycle_trigger", "slave_id", "response_timeout_ms", "registers"});
    } else {
      r.allowOnly({"type", "role", "device", "baud", "parity", "data_bits", "stop_bits", "slave_id",
                   "response_timeout_ms", "link_loss_timeouts", "registers"});
    }
    modbus::RtuLink rtu;
    rtu.device = r.at("device").string();
    if (rtu.device.empty()) r.at("device").failExpected("a serial device path");
    rtu.baud = static_cast<int>(r.integerOr("baud", 50, 4000000, 115200));
    if (auto p = r.find("parity")) rtu.parity = p->oneOf({"N", "E", "O"})[0];
    rtu.dataBits = static_cast<int>(r.integerOr("data_bits", 5, 8, 8));
    rtu.stopBits = static_cast<int>(r.integerOr("stop_bits", 1, 2, 1));
    c.link = rtu;
  }
  // RTU addresses 1..247; TCP unit identifiers 0..255.
  c.slaveId = static_cast<int>(type == "modbus-tcp" ? r.integerOr("slave_id", 0, 255, 1)
                                                    : r.integerOr("slave_id", 1, 247, 1));
  if (auto t = r.find("response_timeout_ms")) {
    c.responseTimeoutMs = t->number(0.1, 10000.0);
  }
  c.linkLossTimeouts = static_cast<int>(r.integerOr("link_loss_timeouts", 1, 1000, 3));
  c.registers = parseModbusRegisterMap(r.at("registers").json(), file, r.childPath("registers"));
  if (server) {
    validateServerMap(c.registers, file, r.childPath("registers"));
    c.server = parseServer(r, type == "modbus-tcp");
  }
  return c;
}

}  // namespace volcomp::config
