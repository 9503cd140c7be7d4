#pragma once
// A CAN transport section as written, before its DBC references are resolved: what
// can_section.cpp parses and can_layout.cpp resolves into a can::CanLayout.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/can/layout.hpp"
#include "volcomp/can/signal.hpp"

namespace volcomp::config {

/// One signal as written in the configuration: a DBC reference or an inline layout.
struct CanSignalRef {
  std::string keyPath;  ///< where it was defined, for messages while resolving
  std::string dbcName;  ///< non-empty: the layout comes from the DBC file, `spec` unused
  can::SignalSpec spec;
};

struct CanSyncFrame {
  std::uint32_t id = 0;
  bool extended = false;
  std::vector<std::uint8_t> data;  ///< payload, 0..8 bytes (a valid FD length when fd)
};

struct CanSection {
  std::string file;     ///< the configuration file (messages)
  std::string keyPath;  ///< the section's key path (messages)
  std::string interfaceName;
  bool fd = false;
  bool bitrateSwitch = true;
  can::Trigger trigger = can::Trigger::Broadcast;
  std::string dbcPath;  ///< "" when none; else resolved against the config file's folder
  double staleTimeoutMs = 100.0;
  double responseTimeoutMs = 10.0;
  std::optional<CanSyncFrame> sync;  ///< present exactly when trigger == Sync

  std::array<CanSignalRef, 3> position{};
  CanSignalRef enable;
  CanSignalRef homed;
  std::vector<CanSignalRef> sequence;
  std::optional<std::array<CanSignalRef, 3>> appliedOffset;

  std::array<CanSignalRef, 3> offset{};
  CanSignalRef status;
  CanSignalRef heartbeat;
};

/// Parses a CAN section (field types and ranges).
CanSection parseCanSection(const nlohmann::json& section, const std::string& file,
                           const std::string& keyPath);

/// Reads the DBC file (when referenced), resolves every signal and checks the layout rules.
can::CanLayout resolveCanSection(const CanSection& section);

}  // namespace volcomp::config
