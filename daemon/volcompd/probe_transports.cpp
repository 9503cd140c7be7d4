// The raw views of the drivers for --probe: each prints what its last read and write carried, with
// the drivers' pure codecs (modbus::describeInputs/Outputs, can::decodeRaw/decode) doing the
// decoding exactly as the loop's reads do.
#include <ostream>
#include <string>
#include <system_error>

#include "commissioning.hpp"
#include "volcomp/can/controller_port.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/display_units.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/modbus/controller_port.hpp"
#include "volcomp/modbus/register_plan.hpp"

namespace volcomp::volcompd {
namespace {

std::string padded(std::string text, std::size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text + ' ';
}

// A scale or counts factor as written in a DBC or register map (0.0001, 10000, 0.5): every
// significant digit, unlike the 3-decimal display of measured values.
std::string factor(double value) {
  return format::general(value, 10);
}

// A signal's raw bits as the integer they encode: two's complement for a signed signal.
std::string rawInteger(std::uint64_t raw, const can::SignalSpec& spec) {
  if (spec.valueType == can::ValueType::Signed && spec.length > 0 && spec.length < 64 &&
      ((raw >> (spec.length - 1)) & 1U) != 0) {
    const std::uint64_t magnitude = (~raw + 1U) & ((std::uint64_t{1} << spec.length) - 1U);
    return "-" + std::to_string(magnitude);
  }
  return std::to_string(raw);
}

std::string millimetres(double mm) {
  return format::signedFixed(mm, 4) + " mm";
}

// ---- Modbus -------------------------------------------------------------------------------

const char* typeName(modbus::RegisterType t) {
  switch (t) {
    case modbus::RegisterType::Int16:
      return "int16";
    case modbus::RegisterType::Uint16:
      return "uint16";
    case modbus::RegisterType::Int32:
      return "int32";
    case modbus::RegisterType::Uint32:
      return "uint32";
    case modbus::RegisterType::Float32:
      return "float32";
    case modbus::RegisterType::Float64:
      return "float64";
  }
  return "?";
}

const char* orderName(modbus::WordOrder o) {
  switch (o) {
    case modbus::WordOrder::ABCD:
      return "ABCD";
    case modbus::WordOrder::CDAB:
      return "CDAB";
    case modbus::WordOrder::BADC:
      return "BADC";
    case modbus::WordOrder::DCBA:
      return "DCBA";
  }
  return "?";
}

void printReadings(std::ostream& out, const modbus::FieldReadings& readings) {
  for (std::size_t i = 0; i < readings.count; ++i) {
    const modbus::FieldReading& r = readings.fields[i];
    std::string where = r.table == modbus::RegisterTable::Input ? "input " : "holding ";
    where += std::to_string(r.address);
    if (r.width > 1) where += "-" + std::to_string(r.address + r.width - 1);
    if (r.bit >= 0) where += " bit " + std::to_string(r.bit);
    std::uint8_t bytes[8];
    for (int k = 0; k < r.width; ++k) {
      bytes[2 * k] = static_cast<std::uint8_t>(r.registers[k] >> 8);
      bytes[2 * k + 1] = static_cast<std::uint8_t>(r.registers[k] & 0xFF);
    }
    std::string decoded;
    if (r.isValue) {
      where += std::string(" ") + typeName(r.format.type) + " " + orderName(r.format.order) + " x" +
               factor(r.format.countsPerMm) + (r.format.sign < 0 ? " sign -1" : "");
      decoded = r.status == modbus::CodecStatus::NotFinite
                    ? "not a number"
                    : millimetres(r.valueMm) + " (" + config::micrometres(r.valueMm) + ")";
    } else if (r.bit >= 0) {
      decoded = r.word != 0 ? "on" : "off";
    } else {
      decoded = std::to_string(r.word);
    }
    out << "  " << padded(r.name, 17) << padded(where, 34) << "raw "
        << padded(format::hexBytes({bytes, static_cast<std::size_t>(2 * r.width)}), 24) << decoded
        << '\n';
  }
}

class ModbusRawView final : public RawView {
 public:
  explicit ModbusRawView(const modbus::ModbusControllerPort& port) : port_(port) {}
  void printInputs(std::ostream& out) const override {
    printReadings(out, modbus::describeInputs(port_.settings().registers, port_.lastHoldingRead(),
                                              port_.lastInputRead()));
  }
  void printOutputs(std::ostream& out) const override {
    printReadings(out, modbus::describeOutputs(port_.settings().registers, port_.lastWrite()));
  }
  std::string readDescription() const override {
    const modbus::RegisterPlan& plan = port_.plan();
    std::string text;
    auto block = [&](const char* fc, const char* table, const modbus::Block& b) {
      if (b.count == 0) return;
      if (!text.empty()) text += " and ";
      text += std::string("one ") + fc + " of " + table + " " + std::to_string(b.start) + "-" +
              std::to_string(b.start + b.count - 1);
    };
    block("FC03", "holding", plan.holdingRead);
    block("FC04", "input", plan.inputRead);
    return text;
  }

 private:
  const modbus::ModbusControllerPort& port_;
};

// ---- CAN ----------------------------------------------------------------------------------

const char* fieldName(can::Field f) {
  static constexpr const char* kNames[] = {
      "position.X",       "position.Y",       "position.Z",       "enable",   "homed",
      "applied_offset.X", "applied_offset.Y", "applied_offset.Z", "sequence", "offset.X",
      "offset.Y",         "offset.Z",         "status",           "heartbeat"};
  return kNames[static_cast<std::size_t>(f)];
}

void printFrames(std::ostream& out, const std::vector<can::FrameLayout>& layouts,
                 const std::vector<can::Frame>& frames) {
  for (std::size_t i = 0; i < layouts.size() && i < frames.size(); ++i) {
    const can::Frame& frame = frames[i];
    out << "  frame " << format::hexId(layouts[i].id, layouts[i].extended) << " ["
        << static_cast<int>(frame.length) << "] "
        << format::hexBytes({frame.data.data(), frame.length}) << '\n';
    for (const can::FieldSignal& s : layouts[i].signals) {
      std::uint64_t raw = 0;
      double physical = 0.0;
      const std::error_code rawError = can::decodeRaw(s.spec, can::payloadOf(frame), raw);
      const std::error_code error = can::decode(s.spec, can::payloadOf(frame), physical);
      const std::string where =
          (s.spec.name.empty() ? std::string("(inline)") : s.spec.name) + " " +
          std::to_string(s.spec.startBit) + "|" + std::to_string(s.spec.length) +
          (s.spec.byteOrder == can::ByteOrder::Intel ? "@1" : "@0") +
          (s.spec.valueType == can::ValueType::Signed ? "-" : "+") + " x" + factor(s.spec.scale);
      std::string decoded;
      if (rawError || error) {
        decoded = "undecodable: " + (rawError ? rawError : error).message();
      } else if (s.field <= can::Field::PositionZ ||
                 (s.field >= can::Field::AppliedX && s.field <= can::Field::AppliedZ) ||
                 (s.field >= can::Field::OffsetX && s.field <= can::Field::OffsetZ)) {
        decoded = millimetres(physical) + " (" + config::micrometres(physical) + ")";
      } else if (s.field == can::Field::Enable || s.field == can::Field::Homed) {
        decoded = physical != 0.0 ? "on" : "off";
      } else {
        decoded = std::to_string(raw);
      }
      out << "    " << padded(fieldName(s.field), 17) << padded(where, 28) << "raw "
          << padded(rawInteger(raw, s.spec), 12) << decoded << '\n';
    }
  }
}

class CanRawView final : public RawView {
 public:
  explicit CanRawView(const can::CanControllerPort& port) : port_(port) {}
  void printInputs(std::ostream& out) const override {
    printFrames(out, port_.layout().inputFrames, port_.lastInputFrames());
  }
  void printOutputs(std::ostream& out) const override {
    printFrames(out, port_.layout().outputFrames, port_.lastOutputFrames());
  }
  std::string readDescription() const override {
    return port_.layout().trigger == can::Trigger::Sync
               ? "a SYNC frame and the answer of every input frame"
               : "the newest complete set of the controller's broadcast frames";
  }

 private:
  const can::CanControllerPort& port_;
};

}  // namespace

ProbeTransport makeProbeTransport(const config::TransportSettings& settings,
                                  const std::string& file) {
  ProbeTransport t;
  const auto* modbusServer = std::get_if<modbus::ModbusSettings>(&settings);
  if (modbusServer != nullptr && modbusServer->role == modbus::ModbusRole::Server) {
    throw config::ConfigError(file, "transport.role",
                              "--probe reads a controller that is a server; with role \"server\" "
                              "the controller is the master: run volcompd and watch its log");
  }
  if (const auto* modbusSettings = std::get_if<modbus::ModbusSettings>(&settings)) {
    std::unique_ptr<modbus::ModbusControllerPort> port;
    try {
      port = std::make_unique<modbus::ModbusControllerPort>(*modbusSettings);
    } catch (const std::system_error& e) {
      throw config::ConfigError(file, "transport",
                                std::string("libmodbus refused the settings: ") + e.what());
    }
    t.raw = std::make_unique<ModbusRawView>(*port);
    t.port = std::move(port);
  } else if (const auto* layout = std::get_if<can::CanLayout>(&settings)) {
    auto port = std::make_unique<can::CanControllerPort>(*layout);
    t.raw = std::make_unique<CanRawView>(*port);
    t.port = std::move(port);
  } else {
    throw config::ConfigError(file, "transport.type",
                              "--probe supports the modbus-tcp, modbus-rtu and can transports");
  }
  return t;
}

}  // namespace volcomp::volcompd
