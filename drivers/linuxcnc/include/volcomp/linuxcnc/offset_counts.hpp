#pragma once
/// Absolute compensation offsets (mm) into LinuxCNC's incremental external-offset counts, one
/// axis.
///
/// LinuxCNC's motion controller keeps a request register R per axis and, every servo period,
/// adds (counts - previous counts) * scale to it, but only while the offset is enabled, not
/// being cleared, all joints are homed and the machine is on; a change at any other time is
/// dropped for good (the previous counts are updated regardless). R is zeroed at every
/// machine-on and by eoffset-clear. So the same counts mean different offsets over time, and
/// the adapter keeps a base B with R = (counts - B) / countsPerMm:
///
///   - while LinuxCNC does not accept changes, the counts are held (a change would be dropped,
///     and writing one could race with acceptance coming back);
///   - when it accepts again, B is taken from the request read back (R has not moved since the
///     counts were held): B = counts - round(R * countsPerMm);
///   - while it accepts, counts = B + round(offset * countsPerMm), and R read back must equal one
///     of the counts written recently (the servo thread adds a change within one period, but it
///     may lag the daemon or stall for a while). Anything else holds the counts for one cycle
///     and takes B afresh on the next.
///
/// What changes R behind the adapter's back (a clear, a machine-on, acceptance lost and regained)
/// takes LinuxCNC tens of milliseconds, so it can only go unseen across a silence of the daemon
/// (the heartbeat watchdog clears the offsets only then). A write after a silence is therefore
/// checked against the last counts alone: the servo thread has seen them long since, and an
/// older value the request happens to equal proves nothing.
///
/// Counts live in 64-bit arithmetic and go onto the 32-bit pin modulo 2^32, which is how
/// LinuxCNC differences them. Pure, noexcept, no allocation.

#include <array>
#include <cstdint>

namespace volcomp::linuxcnc {

class OffsetCounts {
 public:
  /// Earlier writes the request may still reflect while the servo thread lags (64 cycles).
  static constexpr int kHistory = 64;

  explicit OffsetCounts(double countsPerMm) noexcept : countsPerMm_(countsPerMm) {}

  /// Starts from the counts the HAL signal holds now (what LinuxCNC last saw); the next
  /// accepting cycle takes the base from the request read back.
  void adopt(std::int32_t signalCounts) noexcept;

  /// The counts to put on the pin this cycle for `offsetMm`, given whether LinuxCNC accepts
  /// changes and the request it reports (read this cycle, before the write). `afterSilence`:
  /// the previous write was long enough ago that LinuxCNC has seen it (and may have done
  /// something on its own since).
  std::int32_t next(double offsetMm, bool accepting, double requestMm,
                    bool afterSilence = false) noexcept;

  /// True when the next accepting cycle takes the base afresh.
  bool rebasePending() const noexcept { return rebase_; }
  /// Times the base was taken afresh (acceptance regained or the request departed).
  std::uint64_t rebases() const noexcept { return rebases_; }
  /// The counts last put on the pin.
  std::int32_t counts() const noexcept { return static_cast<std::int32_t>(toPin(out_)); }

 private:
  static std::uint32_t toPin(std::int64_t v) noexcept { return static_cast<std::uint32_t>(v); }
  void hold() noexcept;

  double countsPerMm_;
  std::int64_t out_ = 0;                          ///< counts written last (unwrapped)
  std::array<std::int64_t, kHistory> history_{};  ///< counts written before, newest first
  std::int64_t base_ = 0;
  bool rebase_ = true;
  std::uint64_t rebases_ = 0;
};

}  // namespace volcomp::linuxcnc
