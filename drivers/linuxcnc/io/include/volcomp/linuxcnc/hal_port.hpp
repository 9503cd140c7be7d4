#pragma once
/// The LinuxCNC adapter: a HAL userspace component (LinuxCNC's hal.h, liblinuxcnchal) that
/// implements the loop's ControllerPort.
///
/// connect() joins the HAL of a running LinuxCNC (never creating one: when LinuxCNC's HAL shared
/// memory does not exist, it fails with connection_refused and the loop retries with its
/// backoff), registers the component, creates its pins (pins.hpp), links each to its signal and
/// declares the component ready. A component of the same name left behind by a daemon that was
/// killed (its pid is gone) is unlinked from the signals, and this one registers as
/// `<component>-2`, `-3` ... instead (HAL cannot remove another process's component).
///
/// read() takes the commanded positions (axis.L.pos-cmd, without the external offset), enable
/// (the compensation switch, machine on and no clear), homed, the applied offsets
/// (axis.L.eoffset) as the read-back and the optional life counter, straight from HAL shared
/// memory. write() turns the limited offsets into eoffset-counts (offset_counts.hpp), drives
/// eoffset-scale and eoffset-enable, and publishes the offsets, status word, heartbeat and the
/// watchdog bit, which toggles with every write. Neither blocks, allocates or fails once
/// connected: HAL pins are plain shared memory. disconnect() removes the component; the signals
/// keep their last values (offsets held; the HAL snippet's watchdog then clears them).

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <system_error>

#include "volcomp/linuxcnc/offset_counts.hpp"
#include "volcomp/linuxcnc/pins.hpp"
#include "volcomp/linuxcnc/settings.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::linuxcnc {

struct HalPins;  // the pin pointers, in HAL shared memory

/// Diagnostics, read by the owner thread only.
struct HalStatistics {
  std::uint64_t connects = 0;
  std::uint64_t rebases = 0;     ///< counts bases taken afresh (all axes)
  std::uint64_t holdCycles = 0;  ///< writes while LinuxCNC did not accept offset changes
  std::uint64_t reclaimed = 0;   ///< dead predecessors unlinked
};

/// How much an operator needs a notice: Info (the component registered, optional signals left
/// unlinked), Warning (why a connect failed, a dead predecessor replaced, no watchdog signal).
enum class NoticeLevel : std::uint8_t { Info, Warning };
using Notice = std::function<void(NoticeLevel, std::string_view)>;

class HalControllerPort final : public loop::ControllerPort {
 public:
  /// `notice` receives one line for each thing an operator should know about a connect; it is
  /// never called from read() or write().
  explicit HalControllerPort(HalSettings settings, Notice notice = {});
  ~HalControllerPort() override;
  HalControllerPort(const HalControllerPort&) = delete;
  HalControllerPort& operator=(const HalControllerPort&) = delete;

  std::error_code connect() noexcept override;
  void disconnect() noexcept override;
  bool connected() const noexcept override { return componentId_ > 0; }
  std::error_code read(loop::AxisSample& out) noexcept override;
  std::error_code write(const loop::OffsetCommand& command) noexcept override;

  const HalSettings& settings() const noexcept { return settings_; }
  const HalStatistics& statistics() const noexcept { return stats_; }

 private:
  std::error_code attach();
  std::error_code registerComponent();
  std::error_code createPins();
  std::error_code linkPins();
  void say(NoticeLevel level, const std::string& line);

  HalSettings settings_;
  Notice notice_;
  std::string lastNotice_;
  int componentId_ = 0;
  std::string name_;
  HalPins* pins_ = nullptr;
  std::array<bool, kPinCount> linked_{};  ///< per PinId: joined its signal
  std::array<OffsetCounts, 3> counts_;
  bool accepting_ = false;
  std::array<double, 3> requestMm_{};
  bool watchdog_ = false;
  std::chrono::steady_clock::time_point lastWrite_{};
  HalStatistics stats_;
};

}  // namespace volcomp::linuxcnc
