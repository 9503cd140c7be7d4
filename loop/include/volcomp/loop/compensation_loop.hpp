#pragma once
/// The compensation loop: one `step()` per cycle, states and safety rules of docs/daemon.md
/// "States". It depends only on a ControllerPort (link, position source, offset sink), a Clock and
/// a model handle; timing (absolute deadlines) is the scheduler's job.
///
/// States and what each writes (in one transaction: offsets, status word, heartbeat):
///   Starting  nothing, until the applied offsets are read back (offsetReadback) or known zero
///             (nothing written for plcZeroAfter); the limiter then starts from them.
///   Active    enable on, homed, fresh and valid data: model offsets through the limiter.
///   Disabled  enable off or not homed: ramp to zero at max rate, then zero. When enable and
///             homed return, the limiter continues from the read-back if it departs by more
///             than one step (the controller may have ignored the ramp).
///   Fault     stale/invalid input, beyond travel + margin, model error, sustained limiting, a
///             read-back outside the band, failed transaction: ramp to zero; FAULT bit and code.
///             With the fault latch every fault but a failed transaction stays until the
///             controller acknowledges it (fault-ack rising edge, or enable off); otherwise it
///             clears when the cause is gone (the offsets then slew back in through the limiter).
///   LinkLost  transport down: nothing written; reconnect with backoff initial -> 2x -> max; on
///             reconnect back to Starting, i.e. continue from the read-back, never jump.
///   Stopping  after requestStop(): ramp to zero, then write zero with status 0 and finish.
///   Finished  nothing more is done.
/// Position semantics: with `actual` the applied offset (read back, else the last one written) is
/// subtracted from the positions before the model is evaluated, so the offset does not feed back.
///
/// Timing rules (each write is checked against what the controller may be applying then):
///   - the limiter's dt is the measured time since the last write sent, capped at one period,
///     and at most the time since its reply (or giving up on it) plus the smallest recent round
///     trip: a write held up on its way cannot reach the controller bunched with the next;
///   - a write whose outcome is unknown (timeout, mismatched reply) may have been applied: until
///     a write is acknowledged, every value written is within one limiter step of the last
///     acknowledged value and of every value attempted since (or nothing is written);
///   - a cycle whose read-to-write time exceeds readToWriteMax reads again, and writes nothing
///     when the second read is late too: a write is never computed from a stale read-back;
///   - a read-back outside +-max_offset is the fault ReadbackOutOfRange; nothing is written
///     while it lasts.
///
/// step() is noexcept, allocation-free and does no logging; it reports through CycleReport and
/// counters, which the caller logs on state changes only.

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string_view>
#include <system_error>

#include "volcomp/loop/compensation_model.hpp"
#include "volcomp/loop/controller_clock.hpp"
#include "volcomp/loop/direction_tracker.hpp"
#include "volcomp/loop/fault_latch.hpp"
#include "volcomp/loop/latency_compensation.hpp"
#include "volcomp/loop/limiter.hpp"
#include "volcomp/loop/loop_settings.hpp"
#include "volcomp/loop/ports.hpp"
#include "volcomp/loop/reconnect_backoff.hpp"
#include "volcomp/loop/saturation_monitor.hpp"
#include "volcomp/loop/status.hpp"
#include "volcomp/loop/window_minimum.hpp"
#include "volcomp/loop/write_envelope.hpp"

namespace volcomp::loop {

enum class LoopState : std::uint8_t {
  Starting,
  Active,
  Disabled,
  Fault,
  LinkLost,
  Stopping,
  Finished
};

std::string_view stateName(LoopState state) noexcept;

/// Why a cycle that read its inputs wrote nothing.
enum class Withheld : std::uint8_t {
  None,
  /// Both reads of the cycle were older than readToWriteMax when the write was due.
  StaleRead,
  /// The read-back of the applied offsets is outside +-max_offset.
  ReadbackOutOfRange,
  /// After writes with an unknown outcome no value is within one step of every value the
  /// controller may be applying (only when dt shrank below half a period).
  UnknownOutcome,
};

/// What one cycle did.
struct CycleReport {
  LoopState previous = LoopState::Starting;
  LoopState state = LoopState::Starting;
  FaultCode fault = FaultCode::None;
  bool wrote = false;      ///< an offset command was written successfully
  bool goodCycle = false;  ///< read and write succeeded without a fault (Active or Disabled)
  /// The write of this cycle failed on a live link: the controller may or may not apply it.
  bool unknownOutcome = false;
  Withheld withheld = Withheld::None;
  /// A latched fault was acknowledged by the controller in this cycle.
  bool acknowledged = false;
  /// The applied offsets read back went outside +-max_offset in this cycle (at the first read or
  /// after being inside): the values read, mm. Reported once until the read-back is inside again.
  bool readbackLeftBand = false;
  std::array<double, 3> readbackOutsideMm{};
  /// The read-back is inside the band again, after it was outside (reported once).
  bool readbackBackInBand = false;
  /// The saturation warning started in this cycle: the axis (0..2, else -1) and the offset the
  /// model asked for on it (mm).
  int saturationAxis = -1;
  double saturationRequestedMm = 0.0;
  /// Error of the last failed port call in this cycle (read, write or connect), else empty.
  std::error_code error;
  bool stateChanged() const noexcept { return previous != state; }
};

/// Running totals since construction.
struct LoopCounters {
  std::uint64_t cycles = 0;
  std::uint64_t writes = 0;
  std::uint64_t readErrors = 0;   ///< failed reads on a live link
  std::uint64_t writeErrors = 0;  ///< failed writes on a live link
  std::uint64_t linkLosses = 0;
  std::uint64_t connectAttempts = 0;
  std::uint64_t reconnects = 0;  ///< successful connects after a link loss
  std::uint64_t faultCycles = 0;
  std::uint64_t limitedCycles = 0;
  /// Times the limiter was re-seeded from the applied offsets because they departed from what
  /// this loop last wrote (the PLC ramped them out while the daemon was stopped or blocked).
  std::uint64_t resynchronisations = 0;
  /// Writes that failed on a live link, so that the controller may have applied them.
  std::uint64_t unknownOutcomes = 0;
  /// Reads repeated because the read-to-write time exceeded its bound.
  std::uint64_t lateReads = 0;
  /// Cycles that read but wrote nothing (CycleReport::withheld).
  std::uint64_t withheldWrites = 0;
  /// Times the saturation warning started.
  std::uint64_t saturationWarnings = 0;
  /// Cycles whose model evaluation used an extrapolated position on at least one axis (latency
  /// compensation on and the velocity estimate sure).
  std::uint64_t extrapolatedCycles = 0;
  /// Cycles whose hold was predicted to contain a turn of an axis (the offset written is then the
  /// hold's mean of both directions' offsets).
  std::uint64_t turnCycles = 0;
};

class CompensationLoop {
 public:
  /// `model` must not be null. The port is connected by the first step().
  CompensationLoop(ControllerPort& port, const Clock& clock,
                   std::shared_ptr<CompensationModel> model, const LoopSettings& settings);

  /// One cycle. noexcept, allocation-free, no logging.
  CycleReport step() noexcept;

  /// Enter Stopping at the next step (ramp out, write zero and status 0, then Finished).
  void requestStop() noexcept;
  bool finished() const noexcept { return state_ == LoopState::Finished; }

  /// Takes over a validated model between cycles; the offsets slew to its values through the
  /// limiter. Sets MODEL_RELOADED for a while and clears RELOAD_FAILED.
  void setModel(std::shared_ptr<CompensationModel> model) noexcept;
  /// Takes over new settings between cycles (limiter, timeouts, margins; the period and the
  /// read-back mode only change on restart, the caller keeps them). The limiter's limits only
  /// tighten: per axis and limit the stricter of the running and the new value is taken
  /// (reload_limits.hpp); a wider one takes a new loop. Offsets outside a narrowed band return
  /// into it at the rate limit.
  void setSettings(const LoopSettings& settings) noexcept;
  /// A reload was rejected: sets RELOAD_FAILED until the next successful one.
  void noteReloadFailed() noexcept { reloadFailed_ = true; }

  LoopState state() const noexcept { return state_; }
  FaultCode fault() const noexcept { return fault_; }
  /// The fault held by the latch until acknowledged (None when nothing is latched).
  FaultCode latchedFault() const noexcept { return latch_.held(); }
  /// The inputs of the last successful read.
  const AxisSample& lastSample() const noexcept { return sample_; }
  /// Offsets of the last command built (written or attempted).
  const std::array<double, 3>& lastOffsetMm() const noexcept { return command_.offsetMm; }
  std::uint16_t heartbeat() const noexcept { return command_.heartbeat; }
  const LoopCounters& counters() const noexcept { return counters_; }
  const LoopSettings& settings() const noexcept { return settings_; }
  const CompensationModel& model() const noexcept { return *model_; }
  const model::Directions& directions() const noexcept { return tracker_.directions(); }

 private:
  using time_point = Clock::time_point;

  /// What a cycle decided from its inputs, before the limiter.
  struct Decision {
    LoopState next = LoopState::Active;
    FaultCode fault = FaultCode::None;
    std::array<double, 3> targetMm{};
    bool outOfTravel = false;
    bool evaluated = false;  ///< the model gave a valid target this cycle
    bool saturated = false;
    /// The read-back is outside the band in this cycle (not merely a latched fault of it).
    bool readbackOutside = false;
  };

  /// What the read phase of a cycle brought.
  struct Reading {
    bool ended = false;  ///< the cycle ends here, writing nothing (link lost, starting, finished)
    bool fresh = false;  ///< the read was still fresh when the write was due
    Decision decision;
    time_point writeAt{};
  };

  // The phases of step(), in order.
  /// The link is down: try to connect (with backoff). False when the cycle ends here.
  bool reconnect(time_point now, CycleReport& report) noexcept;
  /// The first cycle of a stop sets how long the ramp-out may take.
  void armStopDeadline(time_point now) noexcept;
  /// Read and decide, and read again when the read is no longer fresh when the write is due.
  Reading readAndDecide(time_point now, CycleReport& report) noexcept;
  /// The limiter step towards the decided target, kept within the write envelope. False when no
  /// value may be written (the limiter is left as `before`).
  bool limit(time_point writeAt, Decision& d, const LimiterState& before,
             LimiterOutput& out) noexcept;
  /// Status word, the decided state and the write. True for the last write of a stop.
  bool send(time_point writeAt, const Decision& d, const LimiterState& before,
            const LimiterOutput& out, CycleReport& report) noexcept;
  // How a cycle ends early: finished, or without a write.
  CycleReport finish(CycleReport& report) noexcept;
  CycleReport withhold(Withheld reason, LoopState state, FaultCode fault, bool pastStopDeadline,
                       CycleReport& report) noexcept;

  void enterLinkLost(time_point now, CycleReport& report) noexcept;
  bool tryConnect(time_point now, CycleReport& report) noexcept;
  std::error_code readInputs(time_point readAt, time_point requestAt) noexcept;
  bool takeReading(time_point readAt, std::error_code readError, CycleReport& report) noexcept;
  bool synchronise(time_point now, CycleReport& report) noexcept;
  void trackReadback(bool outside, CycleReport& report) noexcept;
  void followController(time_point now, bool resumed) noexcept;
  void adopt(const std::array<double, 3>& appliedMm) noexcept;
  FaultCode checkInputs(time_point now, std::array<double, 3>& qMm, bool& outOfTravel) noexcept;
  Decision decide(time_point now, bool readFailed, CycleReport& report) noexcept;
  void evaluateModel(time_point now, const std::array<double, 3>& qMm, bool newData, Decision& d,
                     CycleReport& report) noexcept;
  HoldPrediction latencyCompensated(const std::array<double, 3>& qMm, bool newData,
                                    const model::Directions& directions) noexcept;
  ModelOffset holdOffset(const HoldPrediction& hold) noexcept;
  void applyLatch(bool readFailed, Decision& d, CycleReport& report) noexcept;
  bool readbackOutOfRange() const noexcept;
  std::chrono::nanoseconds readToWriteBound(time_point readAt) const noexcept;
  double stepSeconds(time_point writeAt) const noexcept;
  std::uint16_t statusWord(const Decision& d, const LimiterOutput& out, time_point now) noexcept;
  void writeCommand(time_point now, std::uint16_t status, const LimiterState& before,
                    CycleReport& report) noexcept;

  ControllerPort& port_;
  const Clock& clock_;
  std::shared_ptr<CompensationModel> model_;
  LoopSettings settings_;

  LoopState state_ = LoopState::Starting;
  FaultCode fault_ = FaultCode::None;
  FaultLatch latch_;
  bool synced_ = false;
  bool everConnected_ = false;
  bool stopRequested_ = false;
  bool stopDeadlineSet_ = false;
  bool reloadFailed_ = false;
  bool lastWriteFailed_ = false;
  bool sentAny_ = false;
  bool readbackOutside_ = false;  ///< the last read-back checked was outside the band

  AxisSample sample_{};
  OffsetCommand command_{};
  LimiterState limiter_{};
  DirectionTracker tracker_;
  LoopCounters counters_{};

  /// Latency compensation: the velocity estimate, when the controller sampled this cycle's
  /// positions (mid-read) and how long the last acknowledged write took.
  VelocityEstimator estimator_;
  ControllerClock controllerClock_;
  time_point sampledAt_{};  ///< when the controller latched sample_ (mid-read without a timestamp)
  time_point readMidAt_{};  ///< the middle of the read transaction that brought sample_
  bool sameLatch_ = false;  ///< sample_'s timestamp is the previous sample's: nothing new latched
  std::chrono::nanoseconds lastWriteDuration_{0};

  /// What the controller may apply while writes have an unknown outcome.
  WriteEnvelope envelope_;
  SaturationMonitor saturation_;
  ReconnectBackoff backoff_;

  time_point lastWriteTime_{};  // last acknowledged write
  time_point lastSentTime_{};   // last write sent (acknowledged or not)
  time_point lastWriteEnd_{};   // end of the last write transaction (its reply, or giving up)

  /// Round trips of the recent transactions, reads and acknowledged writes (a window, since the
  /// link may change): the smallest is a transaction without queueing. The limiter's dt is counted
  /// from the end of the previous write plus that smallest round trip: a previous write held up on
  /// its way (and so applied late) shortens the next step by as much, so that the two cannot reach
  /// the controller bunched.
  WindowMinimum<128> roundTrips_;
  time_point lastInputChange_{};
  time_point reconnectedUntil_{};
  time_point reloadedUntil_{};
  time_point stopDeadline_{};
  std::uint16_t lastSequence_ = 0;
  std::array<double, 3> lastPositionMm_{};
};

}  // namespace volcomp::loop
