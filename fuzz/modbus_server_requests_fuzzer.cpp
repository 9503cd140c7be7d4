// Requests a Modbus master sends to the daemon in the server role, as the server port decides on
// them before libmodbus answers (drivers/modbus server_bank): the refusal of any function,
// length, quantity or byte count the bank does not serve and of anything outside the bank or
// writing outside the input block, the register ranges of what is let through, and the tracking
// of position writes that triggers a cycle. The bank is the example server configuration's. The
// input is a sequence of PDUs, each a length byte and that many bytes (function code first).
// Invariants: a request let through has ranges, reads only inside the bank and writes only inside
// the input block; a refusal is ILLEGAL FUNCTION, DATA ADDRESS or DATA VALUE; a position set
// completes exactly when every position register has been written since the last complete set.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <set>
#include <span>
#include <string>
#include <variant>

#include "fuzz_support.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/modbus/server_bank.hpp"

namespace {

using namespace volcomp;

const modbus::RegisterMap& exampleMap() {
  static const modbus::RegisterMap map = [] {
    const config::DaemonConfig c =
        config::loadDaemonConfig(VOLCOMP_EXAMPLES_DIR + "/volcompd-modbus-server-tcp.json");
    return std::get<modbus::ModbusSettings>(c.transport).registers;
  }();
  return map;
}

/// Addresses of the position registers (what a complete set must have written).
std::set<std::uint16_t> positionAddresses(const modbus::RegisterMap& map) {
  std::set<std::uint16_t> out;
  for (const modbus::ValueRegister& p : map.position) {
    for (int i = 0; i < modbus::registerWidth(p.format.type); ++i)
      out.insert(static_cast<std::uint16_t>(p.address + i));
  }
  return out;
}

bool inside(const modbus::Block& outer, const modbus::Block& inner) {
  return inner.count == 0 || outer.contains(inner.start, inner.count);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const modbus::RegisterMap& map = exampleMap();
  static const modbus::ServerLayout layout = modbus::layoutServerBank(map);
  static const std::set<std::uint16_t> positions = positionAddresses(map);
  modbus::PositionWriteTracker tracker(map);
  std::set<std::uint16_t> written;

  std::size_t at = 0;
  while (at < size) {
    const std::size_t length = std::min<std::size_t>(data[at], size - at - 1);
    const std::span<const std::uint8_t> pdu(data + at + 1, length);
    at += 1 + length;
    const std::uint8_t refusal = modbus::refuseRequest(layout, pdu);
    if (refusal != 0) {
      fuzz::require(refusal == modbus::kIllegalFunction || refusal == modbus::kIllegalDataAddress ||
                        refusal == modbus::kIllegalDataValue,
                    "a refusal other than function, address or value");
      continue;
    }
    // What is let through is what libmodbus serves without an exception of its own.
    const auto request = modbus::parseServerRequest(pdu);
    fuzz::require(request.has_value(), "a request let through that has no ranges");
    fuzz::require(request->function == pdu[0], "the function is not the PDU's");
    fuzz::require(request->read.count + request->write.count > 0, "a request without a range");
    fuzz::require(inside(layout.bank, request->read), "a read outside the bank let through");
    fuzz::require(inside(layout.masterWrite, request->write),
                  "a write outside the input block let through");
    if (request->write.count == 0) continue;
    for (int i = 0; i < request->write.count; ++i) {
      const auto address = static_cast<std::uint16_t>(request->write.start + i);
      if (positions.count(address) != 0) written.insert(address);
    }
    const bool complete = tracker.onWrite(request->write);
    fuzz::require(complete == (written.size() == positions.size()),
                  "a position set completed before every position register was written, or not "
                  "when it was");
    if (complete) written.clear();
  }
  return 0;
}
