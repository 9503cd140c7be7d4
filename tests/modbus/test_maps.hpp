#pragma once
// The register layout shared by the Modbus tests (the layout of config/examples/sim-vmc.json):
// holding 0..13 inputs (positions int32 at 0/2/4, flags at 6 (bit 0 enable, bit 1 homed),
// life counter at 7, applied offsets int32 at 8/10/12), holding 14..21 outputs (offsets int32 at
// 14/16/18, status 20, heartbeat 21). 10000 counts per mm (0.1 um).

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace volcomp::test {

inline nlohmann::json registersJson(bool fc23 = false) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "defaults": {"type": "int32", "order": "ABCD", "counts_per_mm": 10000},
    "position": {"X": {"address": 0}, "Y": {"address": 2}, "Z": {"address": 4}},
    "enable": {"address": 6, "bit": 0},
    "homed": {"address": 6, "bit": 1},
    "sequence": {"address": 7},
    "applied_offset": {"X": {"address": 8}, "Y": {"address": 10}, "Z": {"address": 12}},
    "offset": {"X": {"address": 14}, "Y": {"address": 16}, "Z": {"address": 18}},
    "status": 20,
    "heartbeat": 21
  })");
  j["fc23"] = fc23;
  return j;
}

inline nlohmann::json tcpTransportJson(std::uint16_t port, bool fc23 = false) {
  return {{"type", "modbus-tcp"},
          {"host", "127.0.0.1"},
          {"port", port},
          {"slave_id", 1},
          {"response_timeout_ms", 100},
          {"link_loss_timeouts", 2},
          {"registers", registersJson(fc23)}};
}

inline nlohmann::json rtuTransportJson(const std::string& device) {
  return {{"type", "modbus-rtu"},
          {"device", device},
          {"baud", 115200},
          {"slave_id", 7},
          {"response_timeout_ms", 200},
          {"link_loss_timeouts", 2},
          {"registers", registersJson()}};
}

/// The server role's transport section over TCP on any free port (port 0), the test layout's
/// bank, with the keys in `extra` added or replaced.
inline nlohmann::json serverTransportJson(const nlohmann::json& extra = nlohmann::json::object()) {
  nlohmann::json j = tcpTransportJson(0);
  j.erase("host");
  j.erase("link_loss_timeouts");
  j["role"] = "server";
  j["registers"].erase("fc23");
  for (const auto& [key, value] : extra.items()) j[key] = value;
  return j;
}

}  // namespace volcomp::test
