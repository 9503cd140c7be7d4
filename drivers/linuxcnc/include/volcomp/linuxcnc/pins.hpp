#pragma once
/// The pins of the adapter's HAL component and the HAL signals they join.
///
/// The component never needs `net` lines naming its pins: when it connects, it links each pin
/// `<component>.<suffix>` to the signal `<prefix>-<suffix with '.' replaced by '-'>`, which the
/// integrator's HAL file declares beside the LinuxCNC pin it carries (config/linuxcnc/volcomp.hal:
/// `net volcomp-x-pos-cmd <= axis.x.pos-cmd`). So the daemon can start before or after LinuxCNC's
/// HAL file has run, be restarted by systemd, and come back under another component name after a
/// crash, without touching the HAL file. A required signal that does not exist makes the connect
/// fail (the daemon retries with its backoff); an optional one is left unlinked.
///
/// Units: positions and offsets in mm (LinuxCNC machine units must be mm); counts are
/// `axis.L.eoffset-counts` units, 1 / countsPerMm mm each.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace volcomp::linuxcnc {

enum class PinType : std::uint8_t { Bit, S32, Float };
enum class PinDirection : std::uint8_t { In, Out };

/// Every pin, in table order (pinTable()[static_cast<int>(id)] describes `id`).
enum class PinId : std::uint8_t {
  PosCmdX,
  PosCmdY,
  PosCmdZ,
  EoffsetX,
  EoffsetY,
  EoffsetZ,
  RequestX,
  RequestY,
  RequestZ,
  MachineOn,
  Homed,
  Enable,
  EoffsetClear,
  Sequence,
  CountsX,
  CountsY,
  CountsZ,
  EoffsetScale,
  EoffsetEnable,
  OffsetX,
  OffsetY,
  OffsetZ,
  Status,
  Heartbeat,
  Watchdog,
  Active,
  Fault,
  FaultCode,
  Pid,
};

inline constexpr int kPinCount = static_cast<int>(PinId::Pid) + 1;

struct PinSpec {
  PinId id;
  std::string_view suffix;  ///< pin name after "<component>."
  PinType type;
  PinDirection direction;
  /// Linking needs the signal to exist (connect fails otherwise); optional pins keep their
  /// default when their signal is missing. The pid pin is never linked.
  bool required;
  bool linked;
  /// The LinuxCNC pin the HAL snippet puts on the same signal ("" when it is up to the
  /// integrator), for documentation and the snippet's test.
  std::string_view linuxcncPin;
  std::string_view meaning;
};

/// All pins, indexed by PinId.
std::span<const PinSpec> pinTable() noexcept;

inline const PinSpec& pinSpec(PinId id) noexcept {
  return pinTable()[static_cast<int>(id)];
}

/// "<component>.<suffix>", e.g. "volcomp.x.pos-cmd".
std::string pinName(std::string_view component, const PinSpec& pin);
/// "<prefix>-<suffix with '.' -> '-'>", e.g. "volcomp-x-pos-cmd".
std::string signalName(std::string_view prefix, const PinSpec& pin);

}  // namespace volcomp::linuxcnc
