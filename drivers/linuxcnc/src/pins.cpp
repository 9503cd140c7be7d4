#include "volcomp/linuxcnc/pins.hpp"

#include <array>

namespace volcomp::linuxcnc {
namespace {

using enum PinType;
constexpr auto In = PinDirection::In;
constexpr auto Out = PinDirection::Out;

constexpr std::array<PinSpec, kPinCount> kPins{{
    {PinId::PosCmdX, "x.pos-cmd", Float, In, true, true, "axis.x.pos-cmd",
     "commanded X position (mm), without the external offset"},
    {PinId::PosCmdY, "y.pos-cmd", Float, In, true, true, "axis.y.pos-cmd",
     "commanded Y position (mm)"},
    {PinId::PosCmdZ, "z.pos-cmd", Float, In, true, true, "axis.z.pos-cmd",
     "commanded Z position (mm)"},
    {PinId::EoffsetX, "x.eoffset", Float, In, true, true, "axis.x.eoffset",
     "external offset LinuxCNC applies now on X (mm): the read-back"},
    {PinId::EoffsetY, "y.eoffset", Float, In, true, true, "axis.y.eoffset",
     "applied external offset on Y (mm)"},
    {PinId::EoffsetZ, "z.eoffset", Float, In, true, true, "axis.z.eoffset",
     "applied external offset on Z (mm)"},
    {PinId::RequestX, "x.eoffset-request", Float, In, true, true, "axis.x.eoffset-request",
     "external offset requested on X (mm): what the counts have added up to"},
    {PinId::RequestY, "y.eoffset-request", Float, In, true, true, "axis.y.eoffset-request",
     "requested external offset on Y (mm)"},
    {PinId::RequestZ, "z.eoffset-request", Float, In, true, true, "axis.z.eoffset-request",
     "requested external offset on Z (mm)"},
    {PinId::MachineOn, "machine-on", Bit, In, true, true, "motion.motion-enabled",
     "the machine is on (LinuxCNC zeroes the offsets at every machine-on)"},
    {PinId::Homed, "homed", Bit, In, true, true, "motion.is-all-homed", "all joints are homed"},
    {PinId::Enable, "enable", Bit, In, false, true, "",
     "compensation switch (default on when its signal is missing)"},
    {PinId::EoffsetClear, "eoffset-clear", Bit, In, false, true, "axis.x.eoffset-clear",
     "the signal that clears the offsets (the heartbeat watchdog's output)"},
    {PinId::Sequence, "sequence", S32, In, false, true, "",
     "optional life counter: stale input when it stops changing"},
    {PinId::CountsX, "x.eoffset-counts", S32, Out, true, true, "axis.x.eoffset-counts",
     "external offset counts on X (LinuxCNC adds their changes)"},
    {PinId::CountsY, "y.eoffset-counts", S32, Out, true, true, "axis.y.eoffset-counts",
     "external offset counts on Y"},
    {PinId::CountsZ, "z.eoffset-counts", S32, Out, true, true, "axis.z.eoffset-counts",
     "external offset counts on Z"},
    {PinId::EoffsetScale, "eoffset-scale", Float, Out, true, true, "axis.x.eoffset-scale",
     "mm per count, 1 / counts_per_mm (all three axes)"},
    {PinId::EoffsetEnable, "eoffset-enable", Bit, Out, true, true, "axis.x.eoffset-enable",
     "external offsets on (all three axes; true while the daemon runs)"},
    {PinId::OffsetX, "x.offset", Float, Out, false, true, "",
     "compensation offset written on X (mm), after the limiter"},
    {PinId::OffsetY, "y.offset", Float, Out, false, true, "", "compensation offset on Y (mm)"},
    {PinId::OffsetZ, "z.offset", Float, Out, false, true, "", "compensation offset on Z (mm)"},
    {PinId::Status, "status", S32, Out, false, true, "",
     "status word (bits as the Modbus status register)"},
    {PinId::Heartbeat, "heartbeat", S32, Out, false, true, "",
     "counter incremented with every write (0..65535)"},
    {PinId::Watchdog, "watchdog", Bit, Out, false, true, "",
     "toggles with every write: feed it to the heartbeat watchdog"},
    {PinId::Active, "active", Bit, Out, false, true, "", "offsets follow the model"},
    {PinId::Fault, "fault", Bit, Out, false, true, "", "a fault is present"},
    {PinId::FaultCode, "fault-code", S32, Out, false, true, "", "fault code (0 = none)"},
    {PinId::Pid, "pid", S32, Out, false, false, "",
     "process id of the daemon (lets a restarted daemon tell a dead predecessor)"},
}};

}  // namespace

std::span<const PinSpec> pinTable() noexcept {
  return kPins;
}

std::string pinName(std::string_view component, const PinSpec& pin) {
  std::string name(component);
  name += '.';
  name += pin.suffix;
  return name;
}

std::string signalName(std::string_view prefix, const PinSpec& pin) {
  std::string name(prefix);
  name += '-';
  for (char c : pin.suffix) name += c == '.' ? '-' : c;
  return name;
}

}  // namespace volcomp::linuxcnc
