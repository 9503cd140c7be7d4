#pragma once
/// Reading a CAN database (DBC file) into can::DbcDatabase: the subset of the Vector DBC format
/// that carries signal layouts.
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

#include <string>
#include <string_view>

#include "volcomp/can/dbc.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::config {

/// Parses DBC text. Throws ConfigError(file, "line N", what was expected).
can::DbcDatabase parseDbc(std::string_view text, const std::string& file);

/// Reads and parses a DBC file (ConfigError naming the file when it cannot be read).
can::DbcDatabase readDbcFile(const std::string& path);

}  // namespace volcomp::config
