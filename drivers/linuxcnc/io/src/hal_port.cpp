#include "volcomp/linuxcnc/hal_port.hpp"

#include <hal.h>
#include <rtapi.h>
#include <signal.h>
#include <sys/ipc.h>
#include <sys/shm.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <utility>

#include "volcomp/linuxcnc/errors.hpp"
#include "volcomp/linuxcnc/pins.hpp"
#include "volcomp/loop/status.hpp"

// Exported by liblinuxcnchal but declared in rtapi.h for realtime modules only.
extern "C" void rtapi_set_msg_handler(rtapi_msg_handler_t handler);

namespace volcomp::linuxcnc {

/// One data pointer per pin, in HAL shared memory (hal_pin_new requires it there).
struct HalPins {
  void* data[kPinCount];
};

namespace {

// LinuxCNC's HAL shared memory key (HAL_KEY in src/hal/hal_priv.h, which the -dev package does
// not install). hal_init() would create the segment when it does not exist, i.e. start an empty
// HAL of its own that LinuxCNC would later attach to: connect() only joins an existing one.
constexpr key_t kHalShmKey = 0x48414C32;

// A gap between two writes after which LinuxCNC has seen the last counts and may have acted on
// its own (clear, machine-on): far longer than a servo period, far shorter than what LinuxCNC
// needs for any of those (offset_counts.hpp).
constexpr auto kSilence = std::chrono::milliseconds(20);

// More components than this under one name means something else is wrong.
constexpr int kMaxNameAttempts = 16;

// hal_lib reports why a call failed only through rtapi_print_msg; keep the last error line so
// that connect() can say it. Only connect() and disconnect() call into hal_lib (one thread).
char lastHalMessage[256] = {};

void keepHalMessage(msg_level_t level, const char* fmt, va_list ap) {
  if (level > RTAPI_MSG_ERR || level == RTAPI_MSG_NONE) return;
  std::vsnprintf(lastHalMessage, sizeof lastHalMessage, fmt, ap);
  for (char* c = lastHalMessage; *c != '\0'; ++c) {
    if (*c == '\n') *c = ' ';
  }
}

std::string takeHalMessage() {
  std::string message(lastHalMessage);
  lastHalMessage[0] = '\0';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

hal_type_t halType(PinType type) noexcept {
  switch (type) {
    case PinType::Bit:
      return HAL_BIT;
    case PinType::S32:
      return HAL_S32;
    case PinType::Float:
      return HAL_FLOAT;
  }
  return HAL_FLOAT;
}

/// True when `pid` is a running volcompd (a reused pid of another program does not count).
bool daemonAlive(int pid) {
  if (pid <= 0) return false;
  if (::kill(pid, 0) != 0 && errno != EPERM) return false;
  std::ifstream comm("/proc/" + std::to_string(pid) + "/comm");
  std::string name;
  std::getline(comm, name);
  return name == "volcompd";
}

constexpr std::array<PinId, 3> kPosCmd{PinId::PosCmdX, PinId::PosCmdY, PinId::PosCmdZ};
constexpr std::array<PinId, 3> kEoffset{PinId::EoffsetX, PinId::EoffsetY, PinId::EoffsetZ};
constexpr std::array<PinId, 3> kRequest{PinId::RequestX, PinId::RequestY, PinId::RequestZ};
constexpr std::array<PinId, 3> kCounts{PinId::CountsX, PinId::CountsY, PinId::CountsZ};
constexpr std::array<PinId, 3> kOffset{PinId::OffsetX, PinId::OffsetY, PinId::OffsetZ};

}  // namespace

namespace {

double getFloat(const HalPins& p, PinId id) noexcept {
  return *static_cast<hal_float_t*>(p.data[static_cast<int>(id)]);
}
bool getBit(const HalPins& p, PinId id) noexcept {
  return *static_cast<hal_bit_t*>(p.data[static_cast<int>(id)]);
}
std::int32_t getS32(const HalPins& p, PinId id) noexcept {
  return *static_cast<hal_s32_t*>(p.data[static_cast<int>(id)]);
}
void setFloat(HalPins& p, PinId id, double v) noexcept {
  *static_cast<hal_float_t*>(p.data[static_cast<int>(id)]) = v;
}
void setBit(HalPins& p, PinId id, bool v) noexcept {
  *static_cast<hal_bit_t*>(p.data[static_cast<int>(id)]) = v;
}
void setS32(HalPins& p, PinId id, std::int32_t v) noexcept {
  *static_cast<hal_s32_t*>(p.data[static_cast<int>(id)]) = v;
}

}  // namespace

HalControllerPort::HalControllerPort(HalSettings settings, Notice notice)
    : settings_(std::move(settings)),
      notice_(std::move(notice)),
      counts_{OffsetCounts(settings_.countsPerMm), OffsetCounts(settings_.countsPerMm),
              OffsetCounts(settings_.countsPerMm)} {}

HalControllerPort::~HalControllerPort() {
  disconnect();
}

void HalControllerPort::say(NoticeLevel level, const std::string& line) {
  // A connect retried with the loop's backoff would repeat the same complaint every attempt.
  if (!notice_ || line == lastNotice_) return;
  lastNotice_ = line;
  notice_(level, line);
}

std::error_code HalControllerPort::connect() noexcept {
  if (connected()) return {};
  try {
    rtapi_set_msg_handler(keepHalMessage);
    const std::error_code ec = attach();
    if (ec) disconnect();
    return ec;
  } catch (...) {
    // Only the notices and names allocate here; out of memory is a failed attempt like any other.
    disconnect();
    return make_error_code(HalErrc::hal_call_failed);
  }
}

std::error_code HalControllerPort::attach() {
  if (::shmget(kHalShmKey, 0, 0) < 0) {
    if (errno == EACCES) {
      say(NoticeLevel::Warning,
          "LinuxCNC's HAL belongs to another user: run volcompd as the user who runs LinuxCNC");
      return std::make_error_code(std::errc::permission_denied);
    }
    // No HAL: LinuxCNC is not running (yet).
    return std::make_error_code(std::errc::connection_refused);
  }
  if (auto ec = registerComponent()) return ec;
  if (auto ec = createPins()) return ec;
  if (auto ec = linkPins()) return ec;
  if (hal_ready(componentId_) != 0) {
    say(NoticeLevel::Warning, "hal_ready failed: " + takeHalMessage());
    return make_error_code(HalErrc::hal_call_failed);
  }
  ++stats_.connects;
  say(NoticeLevel::Info, "joined LinuxCNC's HAL as component '" + name_ + "'");
  lastNotice_.clear();  // the next failure is news again
  return {};
}

std::error_code HalControllerPort::registerComponent() {
  const std::string& base = settings_.component;
  for (int attempt = 1; attempt <= kMaxNameAttempts; ++attempt) {
    const std::string name = attempt == 1 ? base : base + "-" + std::to_string(attempt);
    const int id = hal_init(name.c_str());
    if (id > 0) {
      componentId_ = id;
      name_ = name;
      takeHalMessage();
      return {};
    }
    // The name is taken (or HAL refused for another reason, which the next call shows). Whose
    // is it? A live daemon keeps its pins; a dead one's are unlinked so that this one can take
    // over its signals, whose values (the counts LinuxCNC holds) stay as they are.
    hal_type_t type{};
    hal_data_u* value = nullptr;
    if (hal_get_pin_value_by_name((name + ".pid").c_str(), &type, &value, nullptr) != 0 ||
        type != HAL_S32) {
      say(NoticeLevel::Warning,
          "cannot register HAL component '" + name + "': " + takeHalMessage());
      return make_error_code(HalErrc::hal_call_failed);
    }
    const int pid = value->s;
    if (daemonAlive(pid)) {
      say(NoticeLevel::Warning, "HAL component '" + name + "' belongs to a running volcompd (pid " +
                                    std::to_string(pid) + "); one daemon per LinuxCNC");
      return make_error_code(HalErrc::component_in_use);
    }
    for (const PinSpec& pin : pinTable()) {
      if (pin.linked) hal_unlink(pinName(name, pin).c_str());
    }
    takeHalMessage();
    ++stats_.reclaimed;
    say(NoticeLevel::Warning,
        "HAL component '" + name + "' was left by a volcompd that is gone (pid " +
            std::to_string(pid) + "): its pins are unlinked, registering under another name");
  }
  say(NoticeLevel::Warning, "more than " + std::to_string(kMaxNameAttempts) +
                                " HAL components named '" + base + "*' exist: restart LinuxCNC");
  return make_error_code(HalErrc::component_in_use);
}

std::error_code HalControllerPort::createPins() {
  pins_ = static_cast<HalPins*>(hal_malloc(sizeof(HalPins)));
  if (pins_ == nullptr) {
    say(NoticeLevel::Warning, "hal_malloc failed: HAL shared memory is full (restart LinuxCNC)");
    return make_error_code(HalErrc::hal_call_failed);
  }
  for (const PinSpec& pin : pinTable()) {
    const std::string name = pinName(name_, pin);
    const hal_pin_dir_t dir = pin.direction == PinDirection::In ? HAL_IN : HAL_OUT;
    if (hal_pin_new(name.c_str(), halType(pin.type), dir, &pins_->data[static_cast<int>(pin.id)],
                    componentId_) != 0) {
      say(NoticeLevel::Warning, "cannot create HAL pin '" + name + "': " + takeHalMessage());
      return make_error_code(HalErrc::hal_call_failed);
    }
  }
  // Unlinked inputs read their own default: the switch defaults to on, nothing is cleared.
  setBit(*pins_, PinId::Enable, true);
  setBit(*pins_, PinId::EoffsetClear, false);
  setS32(*pins_, PinId::Pid, static_cast<std::int32_t>(::getpid()));
  setFloat(*pins_, PinId::EoffsetScale, 1.0 / settings_.countsPerMm);
  return {};
}

std::error_code HalControllerPort::linkPins() {
  linked_.fill(false);
  std::string missingOptional;
  for (const PinSpec& pin : pinTable()) {
    if (!pin.linked) continue;
    const std::string pinN = pinName(name_, pin);
    const std::string signal = signalName(settings_.component, pin);
    hal_type_t type{};
    hal_data_u* value = nullptr;
    bool hasWriters = false;
    if (hal_get_signal_value_by_name(signal.c_str(), &type, &value, &hasWriters) != 0) {
      if (pin.required) {
        say(NoticeLevel::Warning,
            "HAL signal '" + signal + "' does not exist: declare it in the HAL file (net " +
                signal + " " + (pin.direction == PinDirection::In ? "<= " : "=> ") +
                std::string(pin.linuxcncPin) + ")");
        return make_error_code(HalErrc::missing_signal);
      }
      missingOptional += (missingOptional.empty() ? "" : ", ") + signal;
      continue;
    }
    if (pin.direction == PinDirection::Out && type == halType(pin.type)) {
      // The first writer drives its own value onto the signal: start from what the signal holds
      // (the counts LinuxCNC last saw, the enable it has), so that joining changes nothing.
      switch (pin.type) {
        case PinType::Bit:
          setBit(*pins_, pin.id, value->b);
          break;
        case PinType::S32:
          setS32(*pins_, pin.id, value->s);
          break;
        case PinType::Float:
          if (pin.id != PinId::EoffsetScale) setFloat(*pins_, pin.id, value->f);
          break;
      }
    }
    if (hal_link(pinN.c_str(), signal.c_str()) != 0) {
      say(NoticeLevel::Warning,
          "cannot link '" + pinN + "' to signal '" + signal + "': " + takeHalMessage());
      return make_error_code(HalErrc::link_failed);
    }
    linked_[static_cast<int>(pin.id)] = true;
  }
  if (!missingOptional.empty()) {
    say(NoticeLevel::Info, "optional HAL signals not declared, left unlinked: " + missingOptional);
  }
  if (!linked_[static_cast<int>(PinId::Watchdog)]) {
    say(NoticeLevel::Warning,
        "no '" + signalName(settings_.component, pinSpec(PinId::Watchdog)) +
            "' signal: LinuxCNC keeps the offsets if volcompd dies (see the HAL snippet)");
  }
  for (std::size_t k = 0; k < 3; ++k) counts_[k].adopt(getS32(*pins_, kCounts[k]));
  accepting_ = false;
  watchdog_ = getBit(*pins_, PinId::Watchdog);
  return {};
}

void HalControllerPort::disconnect() noexcept {
  if (componentId_ > 0) {
    // Removing the component unlinks its pins; the signals keep their values.
    hal_exit(componentId_);
  }
  componentId_ = 0;
  pins_ = nullptr;
  name_.clear();
  accepting_ = false;
}

std::error_code HalControllerPort::read(loop::AxisSample& out) noexcept {
  if (!connected()) return std::make_error_code(std::errc::not_connected);
  const HalPins& p = *pins_;
  for (std::size_t k = 0; k < 3; ++k) {
    out.positionMm[k] = getFloat(p, kPosCmd[k]);
    out.appliedOffsetMm[k] = getFloat(p, kEoffset[k]);
    requestMm_[k] = getFloat(p, kRequest[k]);
  }
  const bool machineOn = getBit(p, PinId::MachineOn);
  const bool clearing = getBit(p, PinId::EoffsetClear);
  out.homed = getBit(p, PinId::Homed);
  out.enable = getBit(p, PinId::Enable) && machineOn && !clearing;
  out.hasAppliedOffsets = true;
  out.hasSequence = linked_[static_cast<int>(PinId::Sequence)];
  out.sequence = static_cast<std::uint16_t>(getS32(p, PinId::Sequence));
  // LinuxCNC adds count changes only while the machine is on, all joints are homed and no clear
  // is active (eoffset-enable is this port's own output, on while connected).
  accepting_ = machineOn && out.homed && !clearing;
  return {};
}

std::error_code HalControllerPort::write(const loop::OffsetCommand& command) noexcept {
  if (!connected()) return std::make_error_code(std::errc::not_connected);
  HalPins& p = *pins_;
  setFloat(p, PinId::EoffsetScale, 1.0 / settings_.countsPerMm);
  setBit(p, PinId::EoffsetEnable, true);
  if (!accepting_) ++stats_.holdCycles;
  const auto now = std::chrono::steady_clock::now();
  const bool afterSilence = now - lastWrite_ > kSilence;
  lastWrite_ = now;
  std::uint64_t rebases = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    setS32(p, kCounts[k],
           counts_[k].next(command.offsetMm[k], accepting_, requestMm_[k], afterSilence));
    setFloat(p, kOffset[k], command.offsetMm[k]);
    rebases += counts_[k].rebases();
  }
  stats_.rebases = rebases;
  setS32(p, PinId::Status, command.status);
  setS32(p, PinId::Heartbeat, command.heartbeat);
  setBit(p, PinId::Active, (command.status & loop::status::kActive) != 0);
  setBit(p, PinId::Fault, (command.status & loop::status::kFault) != 0);
  setS32(p, PinId::FaultCode, static_cast<std::int32_t>(loop::faultCodeOf(command.status)));
  watchdog_ = !watchdog_;
  setBit(p, PinId::Watchdog, watchdog_);
  return {};
}

}  // namespace volcomp::linuxcnc
