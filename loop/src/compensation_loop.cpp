#include "volcomp/loop/compensation_loop.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "volcomp/loop/reload_limits.hpp"

namespace volcomp::loop {
namespace {

bool allFinite(const std::array<double, 3>& v) noexcept {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

double seconds(std::chrono::nanoseconds d) noexcept {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

std::string_view stateName(LoopState state) noexcept {
  switch (state) {
    case LoopState::Starting:
      return "starting";
    case LoopState::Active:
      return "active";
    case LoopState::Disabled:
      return "disabled";
    case LoopState::Fault:
      return "fault";
    case LoopState::LinkLost:
      return "link-lost";
    case LoopState::Stopping:
      return "stopping";
    case LoopState::Finished:
      return "finished";
  }
  return "unknown";
}

CompensationLoop::CompensationLoop(ControllerPort& port, const Clock& clock,
                                   std::shared_ptr<CompensationModel> model,
                                   const LoopSettings& settings)
    : port_(port),
      clock_(clock),
      model_(std::move(model)),
      settings_(settings),
      tracker_(settings.directionHysteresisMm) {
  // Without a read-back the offsets are only known zero once nothing has been written for
  // plcZeroAfter; this process has written nothing so far, so the wait starts now.
  lastWriteTime_ = clock_.now();
  lastSentTime_ = lastWriteTime_;
  lastWriteEnd_ = lastWriteTime_;
}

void CompensationLoop::requestStop() noexcept {
  stopRequested_ = true;
}

void CompensationLoop::setModel(std::shared_ptr<CompensationModel> model) noexcept {
  if (!model) return;
  model_ = std::move(model);
  reloadFailed_ = false;
  reloadedUntil_ = clock_.now() + settings_.noticeHold;
}

// A wider limit is not taken while compensating: what the controller was commissioned against
// changes only through a restart. A narrower one is taken at once; an offset now outside the
// band returns into it at the (stricter) rate, since the limiter never jumps into the band.
void CompensationLoop::setSettings(const LoopSettings& settings) noexcept {
  const auto period = settings_.period;
  const bool readback = settings_.offsetReadback;
  const auto plcZeroAfter = settings_.plcZeroAfter;
  const LimiterSettings limiter = stricterLimits(settings_.limiter, settings.limiter);
  settings_ = settings;
  settings_.period = period;
  settings_.offsetReadback = readback;
  settings_.plcZeroAfter = plcZeroAfter;
  settings_.limiter = limiter;
  tracker_.setHysteresis(settings_.directionHysteresisMm);
  if (!settings_.faultLatch) latch_.release();
}

void CompensationLoop::enterLinkLost(time_point now, CycleReport& report) noexcept {
  port_.disconnect();
  ++counters_.linkLosses;
  state_ = LoopState::LinkLost;
  synced_ = false;
  backoff_.linkLost(now, settings_.reconnectInitial);
  report.state = state_;
}

bool CompensationLoop::tryConnect(time_point now, CycleReport& report) noexcept {
  if (!backoff_.due(now)) return false;
  ++counters_.connectAttempts;
  const std::error_code ec = port_.connect();
  if (ec) {
    report.error = ec;
    state_ = LoopState::LinkLost;
    backoff_.attemptFailed(now, settings_.reconnectInitial, settings_.reconnectMax);
    return false;
  }
  if (everConnected_) {
    ++counters_.reconnects;
    reconnectedUntil_ = now + settings_.noticeHold;
  }
  everConnected_ = true;
  controllerClock_.reset();
  roundTrips_.reset();  // another connection, perhaps another route
  backoff_.connected();
  state_ = LoopState::Starting;
  synced_ = false;
  return true;
}

// The limiter continues from offsets known to be applied: nothing is uncertain any more.
void CompensationLoop::adopt(const std::array<double, 3>& appliedMm) noexcept {
  resetLimiter(limiter_, appliedMm);
  command_.offsetMm = limiter_.offsetMm;
  envelope_.clear();
}

// Where a read-back outside the band starts and where it ends, each reported once: the caller
// logs the values that caused the fault and the recovery, not every cycle in between.
void CompensationLoop::trackReadback(bool outside, CycleReport& report) noexcept {
  if (outside == readbackOutside_) return;
  readbackOutside_ = outside;
  if (outside) {
    report.readbackLeftBand = true;
    report.readbackOutsideMm = sample_.appliedOffsetMm;
  } else {
    report.readbackBackInBand = true;
  }
}

bool CompensationLoop::synchronise(time_point now, CycleReport& report) noexcept {
  std::array<double, 3> applied{};
  if (settings_.offsetReadback) {
    if (!sample_.hasAppliedOffsets) return false;
    if (!allFinite(sample_.appliedOffsetMm)) {
      fault_ = FaultCode::InvalidInput;
      return false;
    }
    // Never take over (and then write) offsets beyond the band: a garbled reply or a controller
    // holding more than this installation allows. The controller's watchdog removes them.
    if (!withinBand(settings_.limiter, sample_.appliedOffsetMm, settings_.readbackResolutionMm)) {
      fault_ = FaultCode::ReadbackOutOfRange;
      trackReadback(true, report);
      return false;
    }
    trackReadback(false, report);
    applied = sample_.appliedOffsetMm;
  } else if (now - lastSentTime_ < settings_.plcZeroAfter) {
    return false;
  }
  adopt(applied);
  tracker_.reset();
  estimator_.reset();
  lastInputChange_ = now;
  lastSequence_ = sample_.sequence;
  lastPositionMm_ = sample_.positionMm;
  latch_.seed(sample_.enable, sample_.hasFaultAck && sample_.faultAck);
  fault_ = FaultCode::None;
  lastWriteFailed_ = false;  // a failure before the resynchronisation says nothing about now
  synced_ = true;
  return true;
}

// The controller may change the applied offsets behind this loop's back while the loop is silent:
// its heartbeat watchdog ramps them out when the daemon was stopped or blocked (SIGSTOP, a stuck
// transaction, a starved CPU). After such a silence the limiter must continue from what is
// applied, as after a reconnect, or the next write would jump. Only after a silence: while the
// loop writes every cycle a read-back that disagrees is more likely frozen registers than a PLC
// acting on its own, and following it would make the written offsets jump. A departure within
// one limiter step is rounding or lag and keeps the limiter's state (its velocity matters for the
// acceleration limit).
void CompensationLoop::followController(time_point now, bool resumed) noexcept {
  const auto silence = now - lastWriteTime_;
  if (silence <= 2 * settings_.period && !(resumed && settings_.offsetReadback)) return;
  std::array<double, 3> applied{};
  if (settings_.offsetReadback) {
    if (!sample_.hasAppliedOffsets || !allFinite(sample_.appliedOffsetMm)) return;
    if (!withinBand(settings_.limiter, sample_.appliedOffsetMm, settings_.readbackResolutionMm)) {
      return;  // decide() faults and nothing is written
    }
    // A life counter that did not move says the registers, the read-back included, are old.
    if (sample_.hasSequence && sample_.sequence == lastSequence_) return;
    applied = sample_.appliedOffsetMm;
    bool departed = false;
    for (std::size_t k = 0; k < 3; ++k) {
      const double toleranceMm = settings_.limiter.axes[k].maxRateMmS * seconds(settings_.period) +
                                 settings_.readbackResolutionMm;
      if (std::abs(applied[k] - limiter_.offsetMm[k]) > toleranceMm) departed = true;
    }
    if (!departed) return;
  } else if (settings_.plcZeroAfter.count() <= 0 || now - lastSentTime_ < settings_.plcZeroAfter) {
    return;  // not silent long enough for the PLC to have zeroed the offsets
  }
  adopt(applied);
  ++counters_.resynchronisations;
}

FaultCode CompensationLoop::checkInputs(time_point now, std::array<double, 3>& qMm,
                                        bool& outOfTravel) noexcept {
  if (!allFinite(sample_.positionMm)) return FaultCode::InvalidInput;
  if (sample_.hasAppliedOffsets && !allFinite(sample_.appliedOffsetMm)) {
    return FaultCode::InvalidInput;
  }

  if (sample_.hasSequence) {
    if (sample_.sequence != lastSequence_) lastInputChange_ = now;
  } else if (settings_.frozenPositionsAreStale) {
    if (sample_.positionMm != lastPositionMm_) lastInputChange_ = now;
  } else {
    lastInputChange_ = now;  // nothing tells fresh from stale data: a read is fresh
  }
  lastSequence_ = sample_.sequence;
  lastPositionMm_ = sample_.positionMm;
  if (now - lastInputChange_ > settings_.staleTimeout) return FaultCode::StaleInput;

  qMm = sample_.positionMm;
  if (settings_.semantics == PositionSemantics::Actual) {
    // The register already holds q + o: evaluate at q, or the offset would feed back on itself.
    const std::array<double, 3>& applied =
        sample_.hasAppliedOffsets ? sample_.appliedOffsetMm : command_.offsetMm;
    for (int k = 0; k < 3; ++k) qMm[k] -= applied[k];
  }

  const auto& travel = model_->travelMm();
  bool beyondMargin = false;
  for (int k = 0; k < 3; ++k) {
    if (!travel[k]) continue;
    const double lo = (*travel[k])[0];
    const double hi = (*travel[k])[1];
    if (qMm[k] < lo || qMm[k] > hi) outOfTravel = true;
    if (qMm[k] < lo - settings_.travelMarginMm || qMm[k] > hi + settings_.travelMarginMm) {
      beyondMargin = true;
    }
  }
  // Unhomed positions are meaningless: the travel check only applies to a homed machine.
  if (beyondMargin && sample_.homed) return FaultCode::OutOfTravel;
  return FaultCode::None;
}

// The model's offset at q, and sustained limiting, which only a valid target can show.
void CompensationLoop::evaluateModel(time_point now, const std::array<double, 3>& qMm, bool newData,
                                     Decision& d, CycleReport& report) noexcept {
  const model::Directions directions = tracker_.update(qMm);
  const ModelOffset result = settings_.latencyCompensation
                                 ? holdOffset(latencyCompensated(qMm, newData, directions))
                                 : model_->offset(qMm, directions);
  if (result.clampedAxes != 0) d.outOfTravel = true;
  if (!allFinite(result.offsetMm)) {
    d.fault = FaultCode::ModelInvalid;
    return;
  }
  if (!result.converged) {
    d.fault = FaultCode::NotConverged;
    return;
  }
  d.targetMm = result.offsetMm;
  d.evaluated = true;
  const Saturation saturation = saturation_.update(
      now, d.targetMm, settings_.limiter, settings_.saturationWarning, settings_.saturationFault);
  d.saturated = saturation.saturated;
  if (saturation.warningStarted) {
    ++counters_.saturationWarnings;
    report.saturationAxis = saturation.axis;
    report.saturationRequestedMm = saturation.requestedMm;
  }
  if (saturation.fault) d.fault = FaultCode::SustainedLimit;
}

// The tracker follows the measured positions only: what the prediction assumes for the hold (an
// extrapolated position, a direction after a predicted turn) never feeds back into it, so an
// extrapolation past a stop cannot turn its direction. Nothing is extrapolated out of the travel
// an axis is in, which would set OUT_OF_TRAVEL for a position not reached.
HoldPrediction CompensationLoop::latencyCompensated(const std::array<double, 3>& qMm, bool newData,
                                                    const model::Directions& directions) noexcept {
  // Samples more than two periods apart belong to another motion (a pause, a late cycle).
  if (newData) estimator_.add(sampledAt_, qMm, 2 * settings_.period + settings_.readToWriteMax);
  // The write leaves about now; it is applied half its transaction later.
  const auto horizon = (clock_.now() - sampledAt_) + lastWriteDuration_ / 2 +
                       settings_.controllerLatency + settings_.period / 2;
  // A latch older than the read (a timestamp says so) is measured, not guessed: the cap grows by
  // that age, up to two periods.
  const auto latchAge = std::clamp<std::chrono::nanoseconds>(
      readMidAt_ - sampledAt_, std::chrono::nanoseconds(0), 2 * settings_.period);
  HoldPrediction hold = predictHold(estimator_, qMm, directions, horizon, settings_.period,
                                    settings_.controllerLatency + 2 * settings_.period + latchAge,
                                    settings_.directionHysteresisMm);
  if (hold.extrapolated > 0) ++counters_.extrapolatedCycles;
  if (hold.turns > 0) ++counters_.turnCycles;
  const auto& travel = model_->travelMm();
  for (std::size_t k = 0; k < 3; ++k) {
    if (!travel[k]) continue;
    const double lo = (*travel[k])[0], hi = (*travel[k])[1];
    if (qMm[k] >= lo && qMm[k] <= hi) hold.qMm[k] = std::clamp(hold.qMm[k], lo, hi);
  }
  return hold;
}

// A hold with turns in it: the model's offset for each piece between turns (directions switched
// at each turn), weighted by the piece's share of the hold. That mean is the constant nearest
// (least squares) to the ideal offset, which jumps at each turn of a bidirectional table.
ModelOffset CompensationLoop::holdOffset(const HoldPrediction& hold) noexcept {
  if (hold.turns == 0) return model_->offset(hold.qMm, hold.directions);
  ModelOffset mean;
  mean.converged = true;
  model::Directions directions = hold.directions;
  double from = 0.0;
  for (std::size_t piece = 0; piece <= hold.turns; ++piece) {
    const double to = piece < hold.turns ? std::clamp(hold.turnFraction[piece], 0.0, 1.0) : 1.0;
    if (to > from) {
      const ModelOffset o = model_->offset(hold.qMm, directions);
      for (std::size_t k = 0; k < 3; ++k) mean.offsetMm[k] += (to - from) * o.offsetMm[k];
      mean.converged = mean.converged && o.converged;
      mean.clampedAxes |= o.clampedAxes;
    }
    if (piece < hold.turns) {
      const std::size_t axis = hold.turnAxis[piece];
      directions[axis] = directions[axis] == model::Direction::Positive
                             ? model::Direction::Negative
                             : model::Direction::Positive;
    }
    from = std::max(from, to);
  }
  return mean;
}

// A latched fault stays until the controller acknowledges it: a rising edge of its fault-ack
// input, or its enable input switched off (the enable toggle). An edge counts only on a read.
void CompensationLoop::applyLatch(bool readFailed, Decision& d, CycleReport& report) noexcept {
  // Only set, never reset: a cycle that reads twice reports an acknowledge of either read.
  if (!readFailed && latch_.acknowledge(sample_.enable, sample_.hasFaultAck && sample_.faultAck)) {
    report.acknowledged = true;
  }
  d.fault = latch_.apply(d.fault, settings_.faultLatch);
}

CompensationLoop::Decision CompensationLoop::decide(time_point now, bool readFailed,
                                                    CycleReport& report) noexcept {
  Decision d;
  const bool outside = !readFailed && readbackOutOfRange();
  if (!readFailed && sample_.hasAppliedOffsets && allFinite(sample_.appliedOffsetMm)) {
    trackReadback(outside, report);
  }
  if (outside) {
    d.fault = FaultCode::ReadbackOutOfRange;
    d.readbackOutside = true;
  } else if (stopRequested_) {
    d.next = LoopState::Stopping;
  } else if (readFailed || lastWriteFailed_) {
    d.fault = FaultCode::TransactionError;
  } else {
    std::array<double, 3> q{};
    // Registers whose life counter did not move hold the previous sample's positions.
    const bool newData = (!sample_.hasSequence || sample_.sequence != lastSequence_) && !sameLatch_;
    d.fault = checkInputs(now, q, d.outOfTravel);
    if (d.fault == FaultCode::None) {
      if (!sample_.enable || !sample_.homed) {
        d.next = LoopState::Disabled;
      } else {
        evaluateModel(now, q, newData, d, report);
      }
    }
  }
  if (!d.evaluated) {
    estimator_.reset();
    saturation_.reset();
  }
  if (stopRequested_) {
    d.next = LoopState::Stopping;
  } else {
    applyLatch(readFailed, d, report);
    if (d.fault != FaultCode::None) d.next = LoopState::Fault;
  }
  if (d.next != LoopState::Active) d.targetMm = {};
  return d;
}

// A read-back outside the band that is not this loop's own last output (which may lie outside
// after a reload narrowed the band, and then returns into it at the rate limit) is a garbled
// reply or offsets this installation does not allow: never taken over.
bool CompensationLoop::readbackOutOfRange() const noexcept {
  if (!settings_.offsetReadback || !sample_.hasAppliedOffsets ||
      !allFinite(sample_.appliedOffsetMm) ||
      withinBand(settings_.limiter, sample_.appliedOffsetMm, settings_.readbackResolutionMm)) {
    return false;
  }
  for (std::size_t k = 0; k < 3; ++k) {
    const double toleranceMm = settings_.limiter.axes[k].maxRateMmS * seconds(settings_.period) +
                               settings_.readbackResolutionMm;
    if (!(std::abs(sample_.appliedOffsetMm[k] - limiter_.offsetMm[k]) <= toleranceMm)) return true;
  }
  return false;
}

std::chrono::nanoseconds CompensationLoop::readToWriteBound(time_point readAt) const noexcept {
  // A cycle that takes over a read-back (after a silence) must write it while it is still true:
  // the controller's own watchdog may be ramping the offsets at that moment.
  const bool silent = !sentAny_ || readAt - lastSentTime_ > 2 * settings_.period;
  return silent ? std::min(settings_.readToWriteMax, settings_.period) : settings_.readToWriteMax;
}

std::uint16_t CompensationLoop::statusWord(const Decision& d, const LimiterOutput& out,
                                           time_point now) noexcept {
  std::uint16_t status = 0;
  switch (d.next) {
    case LoopState::Active:
      status |= status::kActive;
      break;
    case LoopState::Disabled:
      status |= status::kDisabled;
      break;
    case LoopState::Fault:
      status = withFaultCode(status::kFault, d.fault);
      break;
    case LoopState::Stopping:
      status |= status::kStopping;
      break;
    default:
      break;
  }
  if (out.limited) {
    status |= status::kLimited;
    ++counters_.limitedCycles;
  }
  if (now < reconnectedUntil_) status |= status::kReconnected;
  if (d.outOfTravel) status |= status::kOutOfTravel;
  if (now < reloadedUntil_) status |= status::kModelReloaded;
  if (reloadFailed_) status |= status::kReloadFailed;
  if (d.saturated) status |= status::kSaturated;
  if (latch_.holding()) status |= status::kLatched;
  return status;
}

void CompensationLoop::writeCommand(time_point now, std::uint16_t status,
                                    const LimiterState& before, CycleReport& report) noexcept {
  command_.status = status;
  ++command_.heartbeat;
  sentAny_ = true;
  lastSentTime_ = now;
  const std::error_code ec = port_.write(command_);
  lastWriteEnd_ = clock_.now();
  if (!ec) {
    lastWriteDuration_ = lastWriteEnd_ - now;
    roundTrips_.push(lastWriteDuration_);
    ++counters_.writes;
    lastWriteTime_ = now;
    lastWriteFailed_ = false;
    envelope_.clear();
    report.wrote = true;
    return;
  }
  report.error = ec;
  if (isLinkError(ec)) {
    enterLinkLost(now, report);
    // Nothing more is written until the read-back after reconnecting.
    limiter_ = before;
    command_.offsetMm = before.offsetMm;
    return;
  }
  // Timeout, mismatched or exception reply: the request may have been applied (a late answer)
  // or not. The controller now applies the last acknowledged value or one attempted since.
  ++counters_.writeErrors;
  ++counters_.unknownOutcomes;
  lastWriteFailed_ = true;
  report.unknownOutcome = true;
  envelope_.widen(before.offsetMm, command_.offsetMm);
}

// The phases of step() below are always_inline: each is called from step() alone, and as
// out-of-line member functions (GCC does not inline an externally visible function merely because
// it has one caller) they cost about 15 % more instructions per cycle.
[[gnu::always_inline]] inline CycleReport CompensationLoop::finish(CycleReport& report) noexcept {
  state_ = LoopState::Finished;
  report.state = state_;
  return report;
}

bool CompensationLoop::reconnect(time_point now, CycleReport& report) noexcept {
  // Nothing can be written without the link; the PLC drops the offsets on the stalled
  // heartbeat, so a stop does not wait for a reconnection.
  if (stopRequested_) {
    finish(report);
    return false;
  }
  // The driver closed the link between cycles: same as a link error (counted, backoff).
  if (everConnected_ && state_ != LoopState::LinkLost) enterLinkLost(now, report);
  if (!tryConnect(now, report)) {
    report.state = state_;
    return false;
  }
  return true;
}

[[gnu::always_inline]] inline void CompensationLoop::armStopDeadline(time_point now) noexcept {
  if (!stopRequested_ || stopDeadlineSet_) return;
  stopDeadlineSet_ = true;
  // Twice the ramp time plus a second: enough for the ramp with a few failed writes, and
  // bounded, so that a controller refusing writes cannot hold the shutdown beyond the
  // service's stop timeout.
  const auto ramp =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(
          2.0 * rampOutSeconds(settings_.limiter, limiter_.offsetMm) + 1.0));
  stopDeadline_ = now + std::min(ramp, settings_.stopTimeout);
}

// One read transaction into sample_, with when the controller sampled it.
[[gnu::always_inline]] inline std::error_code CompensationLoop::readInputs(
    time_point readAt, time_point requestAt) noexcept {
  const std::error_code readError = port_.read(sample_);
  // The controller answered somewhere inside the transaction: its middle is the best guess,
  // unless the controller says when it latched the positions.
  const time_point replyAt = clock_.now();
  if (!readError) roundTrips_.push(replyAt - requestAt);
  readMidAt_ = readAt + (replyAt - readAt) / 2;
  sampledAt_ = readMidAt_;
  sameLatch_ = false;
  if (!readError && sample_.hasTimestamp) {
    const std::uint64_t before = controllerClock_.stamps();
    sampledAt_ = controllerClock_.latchedAt(sample_.timestampTicks, sample_.timestampTickS, replyAt,
                                            2 * settings_.period);
    sameLatch_ = controllerClock_.stamps() == before;
  }
  return readError;
}

// Returns false when the cycle ends with this read: the link is gone, or the loop is starting and
// may write nothing until the applied offsets are known.
[[gnu::always_inline]] inline bool CompensationLoop::takeReading(time_point readAt,
                                                                 std::error_code readError,
                                                                 CycleReport& report) noexcept {
  if (readError) {
    report.error = readError;
    if (isLinkError(readError)) {
      enterLinkLost(readAt, report);
      if (stopRequested_) finish(report);
      return false;
    }
    ++counters_.readErrors;
  }
  const bool wasSynced = synced_;
  if (!synced_ && (readError || !synchronise(readAt, report))) {
    if (stopRequested_) {
      finish(report);
      return false;
    }
    state_ = LoopState::Starting;
    report.state = state_;
    report.fault = fault_;
    return false;
  }
  if (wasSynced && !readError) {
    const bool resumed = state_ == LoopState::Disabled && sample_.enable && sample_.homed;
    followController(readAt, resumed);
  }
  return true;
}

// Read, decide, and check that the read is still fresh when the write is due; once more if it is
// not (the process was stopped or starved between the two, or the read was slow).
[[gnu::always_inline]] inline CompensationLoop::Reading CompensationLoop::readAndDecide(
    time_point now, CycleReport& report) noexcept {
  Reading reading;
  for (int attempt = 0; attempt < 2 && !reading.fresh; ++attempt) {
    const time_point readAt = attempt == 0 ? now : clock_.now();
    if (attempt > 0) ++counters_.lateReads;
    report.error.clear();
    const time_point requestAt = attempt == 0 ? clock_.now() : readAt;
    const std::error_code readError = readInputs(readAt, requestAt);
    if (!takeReading(readAt, readError, report)) {
      reading.ended = true;
      return reading;
    }
    reading.decision = decide(readAt, static_cast<bool>(readError), report);
    reading.writeAt = clock_.now();
    reading.fresh = reading.writeAt - readAt <= readToWriteBound(readAt);
  }
  return reading;
}

// A stop past its deadline finishes instead: it must not be held up by what withholds the write.
[[gnu::always_inline]] inline CycleReport CompensationLoop::withhold(Withheld reason,
                                                                     LoopState state,
                                                                     FaultCode fault,
                                                                     bool pastStopDeadline,
                                                                     CycleReport& report) noexcept {
  if (pastStopDeadline) return finish(report);
  ++counters_.withheldWrites;
  report.withheld = reason;
  state_ = state;
  fault_ = fault;
  report.fault = fault;
  report.state = state_;
  return report;
}

// dt: the time since the last write, so that a late cycle followed by an on-time one cannot put
// two steps into one period; capped at the period, so that a gap allows no more than one step.
// The controller applied the last write before its reply came back and applies this one after it
// is sent; counting from the reply (plus the round trip of a transaction that was not held up)
// equals counting from the send when the last write was not delayed, and takes off the delay when
// it was (a write stuck in a queue that reaches the controller just before this one). A write
// that got no reply counts from when the loop gave up on it.
[[gnu::always_inline]] inline double CompensationLoop::stepSeconds(
    time_point writeAt) const noexcept {
  if (!sentAny_) return seconds(settings_.period);
  return seconds(std::clamp<std::chrono::nanoseconds>(
      writeAt - lastWriteEnd_ + roundTrips_.min(), std::chrono::nanoseconds(0),
      std::min(writeAt - lastSentTime_, settings_.period)));
}

// No value within one step of everything the controller may be applying: writing nothing is then
// the only output that cannot jump.
[[gnu::always_inline]] inline bool CompensationLoop::limit(time_point writeAt, Decision& d,
                                                           const LimiterState& before,
                                                           LimiterOutput& out) noexcept {
  const double dtS = stepSeconds(writeAt);
  out = limitStep(settings_.limiter, limiter_, d.targetMm, dtS);
  if (out.invalidTarget && d.fault == FaultCode::None) {
    d.fault = FaultCode::ModelInvalid;
    d.next = stopRequested_ ? LoopState::Stopping : LoopState::Fault;
  }
  // Nothing uncertain is the rule: no call into the envelope then.
  if (envelope_.uncertain() && !envelope_.constrain(settings_.limiter, before, dtS, limiter_)) {
    limiter_ = before;
    return false;
  }
  if (limiter_.offsetMm != out.offsetMm) {
    out.offsetMm = limiter_.offsetMm;
    out.limited = true;
  }
  command_.offsetMm = out.offsetMm;
  return true;
}

// The decided state is taken before the write, so that a write that finds the link gone leaves
// the loop in LinkLost. The last write of a stop is zero offsets with status 0 ("inactive").
[[gnu::always_inline]] inline bool CompensationLoop::send(time_point writeAt, const Decision& d,
                                                          const LimiterState& before,
                                                          const LimiterOutput& out,
                                                          CycleReport& report) noexcept {
  std::uint16_t status = statusWord(d, out, writeAt);
  const bool lastOfStop = d.next == LoopState::Stopping && limiterAtZero(limiter_);
  if (lastOfStop) status = 0;
  if (d.fault != FaultCode::None) ++counters_.faultCycles;
  fault_ = d.fault;
  state_ = d.next;
  report.fault = d.fault;
  writeCommand(writeAt, status, before, report);
  return lastOfStop;
}

CycleReport CompensationLoop::step() noexcept {
  const time_point now = clock_.now();
  CycleReport report;
  report.previous = state_;
  ++counters_.cycles;
  if (state_ == LoopState::Finished) return finish(report);
  if (!port_.connected() && !reconnect(now, report)) return report;
  armStopDeadline(now);
  const bool pastStopDeadline = stopRequested_ && now >= stopDeadline_;

  Reading reading = readAndDecide(now, report);
  if (reading.ended) return report;
  Decision& d = reading.decision;
  if (!reading.fresh) {
    return withhold(Withheld::StaleRead, state_, fault_, pastStopDeadline, report);
  }
  if (d.readbackOutside) {
    return withhold(Withheld::ReadbackOutOfRange, LoopState::Fault, d.fault, pastStopDeadline,
                    report);
  }

  const LimiterState before = limiter_;
  LimiterOutput out;
  if (!limit(reading.writeAt, d, before, out)) {
    return withhold(Withheld::UnknownOutcome, state_, fault_, pastStopDeadline, report);
  }
  const bool lastOfStop = send(reading.writeAt, d, before, out, report);

  if (state_ == LoopState::Stopping && ((lastOfStop && report.wrote) || pastStopDeadline)) {
    return finish(report);
  }
  report.state = state_;
  report.goodCycle = report.wrote && d.fault == FaultCode::None &&
                     (state_ == LoopState::Active || state_ == LoopState::Disabled);
  return report;
}

}  // namespace volcomp::loop
