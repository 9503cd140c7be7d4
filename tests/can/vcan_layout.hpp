#pragma once
/// The CAN layout shared by the vcan tests (see the comment on testConfig for the wire format).

#include <nlohmann/json.hpp>

#include "vcan_util.hpp"

namespace volcomp::can::test {

inline nlohmann::json signal(int id, int start, int length, const char* type, double scale) {
  return {{"id", id}, {"start_bit", start}, {"length", length}, {"type", type}, {"scale", scale}};
}

/// Inputs: 0x100 = X (int24 @0, 0.1 µm), Y (int24 @24), sequence (uint8 @56);
///         0x101 = Z (int32 @0, 0.1 µm), enable (bit 32), homed (bit 33), sequence (uint8 @56).
/// Outputs: 0x300 = offsets X, Y, Z (int16 @0, @16, @32, 1 µm), status (uint16 @48);
///          0x301 = heartbeat (uint8 @0).
inline nlohmann::json testConfig(const char* trigger = "broadcast", double staleMs = 1000.0) {
  nlohmann::json c{{"interface", interfaceName()},
                   {"trigger", trigger},
                   {"timeouts", {{"stale_ms", staleMs}, {"response_ms", 500}}},
                   {"inputs",
                    {{"position",
                      {{"X", signal(0x100, 0, 24, "signed", 0.0001)},
                       {"Y", signal(0x100, 24, 24, "signed", 0.0001)},
                       {"Z", signal(0x101, 0, 32, "signed", 0.0001)}}},
                     {"enable", signal(0x101, 32, 1, "unsigned", 1)},
                     {"homed", signal(0x101, 33, 1, "unsigned", 1)},
                     {"sequence", nlohmann::json::array({signal(0x100, 56, 8, "unsigned", 1),
                                                         signal(0x101, 56, 8, "unsigned", 1)})}}},
                   {"outputs",
                    {{"offset",
                      {{"X", signal(0x300, 0, 16, "signed", 0.001)},
                       {"Y", signal(0x300, 16, 16, "signed", 0.001)},
                       {"Z", signal(0x300, 32, 16, "signed", 0.001)}}},
                     {"status", signal(0x300, 48, 16, "unsigned", 1)},
                     {"heartbeat", signal(0x301, 0, 8, "unsigned", 1)}}}};
  if (std::string(trigger) == "sync") c["sync"] = {{"id", 0x80}};
  return c;
}

}  // namespace volcomp::can::test
