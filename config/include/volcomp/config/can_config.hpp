#pragma once
/// The CAN transport section of a daemon (and simulator) configuration. Plain data; the codec,
/// the DBC importer and the SocketCAN driver live in volcomp::can, which also resolves the DBC
/// references and checks the frame layout (resolveCanConfig).
///
/// JSON shape (key paths relative to the section; everything not marked optional is required):
///   {
///     "type": "can",                               optional (the daemon's transport selector)
///     "interface": "can0",
///     "fd": false,                                 optional: CAN FD frames (payload up to 64 B)
///     "bitrate_switch": true,                      optional, fd only: set BRS on sent frames
///     "trigger": "broadcast" | "sync",
///     "dbc": "machine.dbc",                        optional, relative to this file's folder
///     "timeouts": {"stale_ms": 100, "response_ms": 10},                    optional
///     "sync": {"id": "0x080", "extended": false, "data": [0]},       sync trigger only
///     "inputs": {
///       "position": {"X": SIGNAL, "Y": SIGNAL, "Z": SIGNAL},     mm
///       "enable": SIGNAL, "homed": SIGNAL,                        true when != 0
///       "sequence": SIGNAL | [SIGNAL, ...],                       optional: one per input frame
///       "applied_offset": {"X": SIGNAL, "Y": SIGNAL, "Z": SIGNAL} optional read-back, mm
///     },
///     "outputs": {
///       "offset": {"X": SIGNAL, "Y": SIGNAL, "Z": SIGNAL},       mm
///       "status": SIGNAL, "heartbeat": SIGNAL
///     }
///   }
/// SIGNAL is either {"dbc": "Message.Signal"} / {"dbc": "Signal"} (layout from the DBC file) or
///   {"id": 256 | "0x100", "extended": false, "start_bit": 0, "length": 32,
///    "byte_order": "intel" | "motorola", "type": "unsigned" | "signed" | "float32" | "float64",
///    "scale": 0.001, "offset": 0.0, "min": -1000, "max": 1000, "unit": "mm"}
///   with extended (false), byte_order ("intel"), type ("unsigned"), scale (1), offset (0),
///   min/max (0/0 = unchecked) and unit optional. physical = raw * scale + offset (DBC rule).
///
/// Triggers: `broadcast` — the controller sends its input frames by itself; the daemon uses the
/// newest complete set (every input frame received, all carrying the same sequence counter when
/// there is more than one input frame). `sync` — each cycle the daemon sends the SYNC frame and
/// waits up to response_ms for every input frame.
/// Timeouts: stale_ms (broadcast: the newest complete set may be this old; default 100),
/// response_ms (sync: wait for the answer; default 10).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/config/config_error.hpp"

namespace volcomp::config {

enum class CanByteOrder : std::uint8_t { Intel, Motorola };
enum class CanValueType : std::uint8_t { Unsigned, Signed, Float32, Float64 };
enum class CanTrigger : std::uint8_t { Broadcast, Sync };

/// One signal as written in the configuration: a DBC reference or an inline layout.
struct CanSignalConfig {
  std::string keyPath;  ///< where it was defined, for messages while resolving
  std::string dbcName;  ///< non-empty: the layout comes from the DBC file, fields below unused
  std::uint32_t frameId = 0;
  bool extended = false;
  unsigned startBit = 0;
  unsigned length = 1;
  CanByteOrder byteOrder = CanByteOrder::Intel;
  CanValueType valueType = CanValueType::Unsigned;
  double scale = 1.0;
  double offset = 0.0;
  double minimum = 0.0;
  double maximum = 0.0;
  std::string unit;
};

struct CanSyncFrame {
  std::uint32_t id = 0;
  bool extended = false;
  std::vector<std::uint8_t> data;  ///< payload, 0..8 bytes (a valid FD length when fd)
};

struct CanConfig {
  std::string file;     ///< the configuration file (messages)
  std::string keyPath;  ///< the section's key path (messages)
  std::string interfaceName;
  bool fd = false;
  bool bitrateSwitch = true;
  CanTrigger trigger = CanTrigger::Broadcast;
  std::string dbcPath;  ///< "" when none; else resolved against the config file's folder
  double staleTimeoutMs = 100.0;
  double responseTimeoutMs = 10.0;
  std::optional<CanSyncFrame> sync;  ///< present exactly when trigger == Sync

  std::array<CanSignalConfig, 3> position{};
  CanSignalConfig enable;
  CanSignalConfig homed;
  std::vector<CanSignalConfig> sequence;
  std::optional<std::array<CanSignalConfig, 3>> appliedOffset;

  std::array<CanSignalConfig, 3> offset{};
  CanSignalConfig status;
  CanSignalConfig heartbeat;
};

/// Parses a CAN section (field types and ranges). Layout rules that need the DBC (frame fit,
/// overlaps, one sequence counter per input frame…) are checked by volcomp::can::resolveCanConfig.
CanConfig parseCanConfig(const nlohmann::json& section, const std::string& file,
                         const std::string& keyPath);

}  // namespace volcomp::config
