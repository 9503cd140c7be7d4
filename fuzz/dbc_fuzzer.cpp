// CAN databases (DBC files referenced by a CAN transport section): text -> can::DbcDatabase as
// readDbcFile reads it. Every signal accepted has a valid layout that fits its message, and
// decodes and encodes through the signal codec without reading or writing outside the payload.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "fuzz_support.hpp"
#include "volcomp/can/dbc.hpp"
#include "volcomp/can/frame.hpp"
#include "volcomp/can/signal.hpp"
#include "volcomp/config/dbc_file.hpp"

namespace {

using namespace volcomp;

void exercise(const can::DbcMessage& message) {
  fuzz::require(can::isValidId(message.id, message.extended), "message id out of range");
  fuzz::require(message.length <= can::kFdMaxLength, "message longer than 64 bytes");
  for (const can::DbcSignal& signal : message.signals) {
    const can::SignalSpec& spec = signal.spec;
    fuzz::require(can::layoutProblem(spec).empty(), "a signal with a bad layout was accepted");
    fuzz::require(spec.frameId == message.id && spec.extended == message.extended,
                  "a signal names another message");
    // A payload exactly as long as the signal needs: the codec must stay inside it.
    const std::size_t needed = can::bytesNeeded(spec);
    if (needed > can::kFdMaxLength) continue;
    std::array<std::uint8_t, can::kFdMaxLength> bytes{};
    const std::span<std::uint8_t> payload(bytes.data(), needed);
    for (const std::uint8_t fill : {std::uint8_t{0x00}, std::uint8_t{0xA5}, std::uint8_t{0xFF}}) {
      for (std::uint8_t& b : payload) b = fill;
      std::uint64_t raw = 0;
      fuzz::require(!can::decodeRaw(spec, payload, raw), "raw decode failed inside the payload");
      double physical = 0.0;
      if (!can::decode(spec, payload, physical)) {
        fuzz::require(std::isfinite(physical), "a decoded value is not finite");
        can::encode(spec, physical, payload);
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const can::DbcDatabase db = config::parseDbc(fuzz::text(data, size), "fuzz.dbc");
    for (const can::DbcMessage& message : db.messages) {
      exercise(message);
      fuzz::require(db.message(message.id, message.extended) != nullptr, "message not found");
      for (const can::DbcSignal& signal : message.signals) {
        fuzz::require(!db.find(message.name + "." + signal.spec.name).empty(),
                      "a signal is not found by its qualified name");
      }
    }
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
