#pragma once
/// A CAN link's resolved settings: the interface, the trigger, timeouts and every frame the driver
/// receives or sends with the signals it carries. What the driver (and the controller node of the
/// simulator and tests) works from; config/can_config.hpp builds it from a transport section
/// (resolving DBC references) and checks the layout rules listed there.
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "volcomp/can/frame.hpp"
#include "volcomp/can/signal.hpp"

namespace volcomp::can {

/// How the controller's input frames are triggered: `Broadcast` — the controller sends them by
/// itself; the daemon uses the newest complete set (every input frame received, all carrying the
/// same sequence counter when there is more than one input frame). `Sync` — each cycle the daemon
/// sends the SYNC frame and waits up to the response timeout for every input frame.
enum class Trigger : std::uint8_t { Broadcast, Sync };

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
  bool operator==(const FieldSignal&) const = default;
};

/// One frame the driver receives or sends, with the signals it carries.
struct FrameLayout {
  std::uint32_t id = 0;
  bool extended = false;
  std::size_t length = 0;  ///< bytes: minimum accepted (inputs) / sent (outputs)
  std::vector<FieldSignal> signals;
  bool operator==(const FrameLayout&) const = default;
};

struct CanLayout {
  std::string interfaceName;
  bool fd = false;
  bool bitrateSwitch = true;
  Trigger trigger = Trigger::Broadcast;
  std::chrono::microseconds staleTimeout{100000};
  std::chrono::microseconds responseTimeout{10000};
  std::optional<Frame> syncFrame;
  bool hasSequence = false;
  bool hasAppliedOffsets = false;
  std::vector<FrameLayout> inputFrames;  ///< in order of first appearance in the config
  std::vector<FrameLayout> outputFrames;
  bool operator==(const CanLayout&) const = default;
};

}  // namespace volcomp::can
