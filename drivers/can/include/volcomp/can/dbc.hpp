#pragma once
/// A subset of the Vector DBC format, enough to take signal layouts from a controller's CAN
/// database instead of typing them into the daemon configuration.
///
/// Understood lines (everything else, e.g. VERSION, NS_, BU_, CM_, BA_, VAL_, is skipped):
///   BO_ <id> <name>: <length> <transmitter>
///       id in decimal; bit 31 set means a 29-bit identifier (id & 0x1FFFFFFF); length in bytes
///       (0..8, or a CAN FD length up to 64).
///   SG_ <name> [<mux>] : <start>|<length>@<order><sign> (<scale>,<offset>) [<min>|<max>] "<unit>"
///   <receivers>
///       order 1 = Intel (little-endian), 0 = Motorola (big-endian, start bit = MSB); sign + / -.
///       The optional multiplexer indicator (M, mNN) is kept so that users of such signals can
///       be refused: multiplexing is not supported.
///   SIG_VALTYPE_ <id> <signal> : <1|2>;   1 = IEEE float32, 2 = IEEE float64.
/// The pseudo-message VECTOR__INDEPENDENT_SIG_MSG (id 0xC0000000) and its signals are skipped.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "volcomp/can/signal.hpp"

namespace volcomp::can {

struct DbcSignal {
  SignalSpec spec;          ///< layout, with the message's identifier
  std::string multiplexer;  ///< "" for a plain signal, else the DBC indicator ("M", "m3")
};

struct DbcMessage {
  std::string name;
  std::uint32_t id = 0;
  bool extended = false;
  std::size_t length = 0;  ///< payload bytes
  std::vector<DbcSignal> signals;
};

struct DbcDatabase {
  std::vector<DbcMessage> messages;

  /// Signals matching `name`: "Message.Signal", or a bare "Signal" (all messages searched).
  /// Empty when none match; more than one when a bare name is ambiguous.
  std::vector<const DbcSignal*> find(std::string_view name) const;
  /// The message with this identifier, or nullptr.
  const DbcMessage* message(std::uint32_t id, bool extended) const noexcept;
};

/// Parses DBC text. Throws volcomp::config::ConfigError(file, "line N", what was expected).
DbcDatabase parseDbc(std::string_view text, const std::string& file);

/// Reads and parses a DBC file (ConfigError naming the file when it cannot be read).
DbcDatabase readDbcFile(const std::string& path);

}  // namespace volcomp::can
