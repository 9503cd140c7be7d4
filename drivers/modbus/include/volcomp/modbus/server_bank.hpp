#pragma once
/// The server role's register bank, as pure functions of the register map: where the bank lies,
/// which requests of a master it accepts, and when the master's writes complete a position set.
/// The server port (io/server_port.hpp) serves the bank with libmodbus; these parts decide.
///
/// The bank is one block of holding registers covering every input the master writes (positions,
/// enable/homed, fault ack, life counter, applied offsets: the "input block", the plan's
/// holdingRead) and every output the master reads (offsets, status, heartbeat: the plan's write
/// block). The master may read anywhere in the bank (FC03, or the read half of FC23) and write
/// only inside the input block (FC06, FC16, FC22, the write half of FC23), never an output
/// register; anything else is refused with an exception (refuseRequest).

#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "volcomp/modbus/register_plan.hpp"
#include "volcomp/modbus/registers.hpp"

namespace volcomp::modbus {

struct ServerLayout {
  Block bank;         ///< all holding registers the server holds (inputs, outputs, gaps between)
  Block masterWrite;  ///< the input block: the only registers the master may write
  Block output;       ///< offsets, status, heartbeat: written by the loop, read by the master
};

/// The layout of a validated map whose inputs are all holding registers (the server role's
/// configuration rule; config::parseModbusSettings checks it).
ServerLayout layoutServerBank(const RegisterMap& map) noexcept;

/// The register ranges one request touches (count 0: none). `function` is the Modbus function
/// code.
struct ServerRequest {
  std::uint8_t function = 0;
  Block read;
  Block write;
};

/// Reads function code and ranges from a request PDU (function code first, as after the ADU's
/// header). FC03, FC06, FC16, FC22 and FC23 give ranges; other functions give the function only.
/// nullopt when the PDU is too short for its function.
std::optional<ServerRequest> parseServerRequest(std::span<const std::uint8_t> pdu) noexcept;

/// Modbus exception codes the server answers with (Modbus Application Protocol v1.1b3, 7).
inline constexpr std::uint8_t kIllegalFunction = 1;
inline constexpr std::uint8_t kIllegalDataAddress = 2;
inline constexpr std::uint8_t kIllegalDataValue = 3;

/// Decides a whole request PDU (exactly its bytes, function code first) before libmodbus sees
/// it, so that libmodbus answers only requests it serves without an exception (it waits out its
/// response timeout before some of its own exception replies, which would hold every other
/// connection). 0: FC03, FC06, FC16, FC22 or FC23, of the function's exact length, with legal
/// quantities and a byte count that matches, reading inside the bank and writing inside the input
/// block. Otherwise the exception, checked in the order of the protocol's request processing:
/// kIllegalFunction for any other function (FC04 and the coil functions included: the bank has
/// holding registers only; a function code of 0x80 or above is no request), kIllegalDataValue for
/// a wrong length, a quantity of 0 or above the function's maximum, or a byte count that does not
/// match, kIllegalDataAddress for a range outside the bank or a write outside the input block
/// (or onto an output register).
std::uint8_t refuseRequest(const ServerLayout& layout, std::span<const std::uint8_t> pdu) noexcept;

/// Tracks the master's writes of the position registers: a position set is complete once every
/// register of positions X, Y and Z has been written since the last complete set (in one
/// request or several; a float64 position has 4 registers, so up to 12 are tracked).
class PositionWriteTracker {
 public:
  explicit PositionWriteTracker(const RegisterMap& map) noexcept;
  /// Notes a write of `write` (already accepted); true when it completes a position set (the
  /// tracker then starts over).
  bool onWrite(Block write) noexcept;
  /// Forgets a partly written set (a new master connection).
  void reset() noexcept { written_ = 0; }

 private:
  std::array<std::uint16_t, 12> addresses_{};
  int count_ = 0;
  std::uint16_t written_ = 0;  // bit i: addresses_[i] written since the last complete set
  std::uint16_t all_ = 0;
};

/// True when `address` (IPv4, network byte order) may connect: `allowed` is empty (anyone) or
/// holds it.
bool clientAllowed(std::uint32_t address, std::span<const std::uint32_t> allowed) noexcept;

}  // namespace volcomp::modbus
