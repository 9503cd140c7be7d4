#pragma once
/// The CAN configuration after DBC references are resolved and the frame layout is checked:
/// what the driver (and the simulated controller node) works from.
///
/// Rules checked by resolveCanConfig (each violation is a ConfigError at the signal's key path):
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

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "volcomp/can/frame.hpp"
#include "volcomp/can/signal.hpp"
#include "volcomp/config/can_config.hpp"

namespace volcomp::can {

/// Where a decoded input goes / where an encoded output comes from.
enum class Field : std::uint8_t {
  PositionX,
  PositionY,
  PositionZ,
  Enable,
  Homed,
  AppliedX,
  AppliedY,
  AppliedZ,
  Sequence,
  OffsetX,
  OffsetY,
  OffsetZ,
  Status,
  Heartbeat,
};
inline constexpr std::size_t kFieldCount = 14;

struct FieldSignal {
  Field field;
  SignalSpec spec;
};

/// One frame the driver receives or sends, with the signals it carries.
struct FrameLayout {
  std::uint32_t id = 0;
  bool extended = false;
  std::size_t length = 0;  ///< bytes: minimum accepted (inputs) / sent (outputs)
  std::vector<FieldSignal> signals;
};

struct CanLayout {
  std::string interfaceName;
  bool fd = false;
  bool bitrateSwitch = true;
  config::CanTrigger trigger = config::CanTrigger::Broadcast;
  std::chrono::microseconds staleTimeout{100000};
  std::chrono::microseconds responseTimeout{10000};
  std::optional<Frame> syncFrame;
  bool hasSequence = false;
  bool hasAppliedOffsets = false;
  std::vector<FrameLayout> inputFrames;  ///< in order of first appearance in the config
  std::vector<FrameLayout> outputFrames;
};

/// Loads the DBC file (when referenced), resolves every signal and checks the rules above.
/// Throws config::ConfigError naming the configuration file (or the DBC file) and key path.
CanLayout resolveCanConfig(const config::CanConfig& config);

/// Parses and resolves a CAN section in one step.
CanLayout loadCanLayout(const nlohmann::json& section, const std::string& file,
                        const std::string& keyPath);

}  // namespace volcomp::can
