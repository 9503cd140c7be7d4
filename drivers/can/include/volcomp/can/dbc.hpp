#pragma once
/// A CAN database (the subset of the Vector DBC format config/dbc_file.hpp reads): messages and
/// the layouts of their signals, to take signal layouts from a controller's CAN database instead
/// of typing them into the daemon configuration.

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

}  // namespace volcomp::can
