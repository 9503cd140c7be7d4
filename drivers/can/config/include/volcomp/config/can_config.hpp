#pragma once
/// The CAN transport section of a daemon (and simulator) configuration, read into the resolved
/// can::CanLayout the driver and the simulated controller work from: DBC references are looked
/// up in the DBC file the section names and the frame layout is checked.
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

/// Rules checked by loadCanLayout (each violation is a ConfigError at the signal's key path):
/// - every signal's layout is valid and fits its frame: 8 bytes classical, 64 bytes FD, and the
///   DBC message length when the signal comes from the DBC;
/// - signals sharing a frame do not overlap; no frame is both an input and an output, and the
///   SYNC frame is neither;
/// - status is an unsigned integer of at least 16 bits with scale 1 and offset 0 (the status word
///   is 16 bits); heartbeat and sequence counters are unsigned integers with scale 1 and
///   offset 0 (the heartbeat wraps modulo 2^length: it is a counter);
/// - at most one sequence counter per input frame; with the broadcast trigger and more than one
///   input frame, every input frame carries one (that is how a consistent set is recognised);
/// - multiplexed DBC signals are refused.

#include <string>

#include <nlohmann/json.hpp>

#include "volcomp/can/layout.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::config {

/// Parses a CAN section, reads its DBC file (when referenced, relative to `file`'s folder),
/// resolves every signal and checks the rules above. Throws ConfigError naming `file` (or the
/// DBC file) and the key path under `keyPath`.
can::CanLayout loadCanLayout(const nlohmann::json& section, const std::string& file,
                             const std::string& keyPath);

}  // namespace volcomp::config
