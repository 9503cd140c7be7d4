#include "volcomp/loop/compensation_loop.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

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

void CompensationLoop::setSettings(const LoopSettings& settings) noexcept {
  const auto period = settings_.period;
  const bool readback = settings_.offsetReadback;
  const auto plcZeroAfter = settings_.plcZeroAfter;
  settings_ = settings;
  settings_.period = period;
  settings_.offsetReadback = readback;
  settings_.plcZeroAfter = plcZeroAfter;
  tracker_.setHysteresis(settings_.directionHysteresisMm);
}

void CompensationLoop::enterLinkLost(time_point now, CycleReport& report) noexcept {
  port_.disconnect();
  ++counters_.linkLosses;
  state_ = LoopState::LinkLost;
  synced_ = false;
  backoff_ = settings_.reconnectInitial;
  nextConnectAttempt_ = now + backoff_;
  report.state = state_;
}

bool CompensationLoop::tryConnect(time_point now, CycleReport& report) noexcept {
  if (now < nextConnectAttempt_) return false;
  ++counters_.connectAttempts;
  const std::error_code ec = port_.connect();
  if (ec) {
    report.error = ec;
    state_ = LoopState::LinkLost;
    backoff_ = backoff_.count() == 0 ? settings_.reconnectInitial
                                     : std::min(2 * backoff_, settings_.reconnectMax);
    nextConnectAttempt_ = now + backoff_;
    return false;
  }
  if (everConnected_) {
    ++counters_.reconnects;
    reconnectedUntil_ = now + settings_.noticeHold;
  }
  everConnected_ = true;
  backoff_ = std::chrono::nanoseconds(0);
  state_ = LoopState::Starting;
  synced_ = false;
  return true;
}

bool CompensationLoop::synchronise(time_point now) noexcept {
  std::array<double, 3> applied{};
  if (settings_.offsetReadback) {
    if (!sample_.hasAppliedOffsets) return false;
    if (!allFinite(sample_.appliedOffsetMm)) {
      fault_ = FaultCode::InvalidInput;
      return false;
    }
    applied = sample_.appliedOffsetMm;
  } else if (now - lastWriteTime_ < settings_.plcZeroAfter) {
    return false;
  }
  resetLimiter(limiter_, applied);
  command_.offsetMm = limiter_.offsetMm;
  tracker_.reset();
  lastInputChange_ = now;
  lastSequence_ = sample_.sequence;
  lastPositionMm_ = sample_.positionMm;
  fault_ = FaultCode::None;
  lastWriteFailed_ = false;  // a failure before the resynchronisation says nothing about now
  synced_ = true;
  return true;
}

// The controller may change the applied offsets behind this loop's back while the loop is silent:
// its heartbeat watchdog ramps them out when the daemon was stopped or blocked (SIGSTOP, a stuck
// transaction, a starved CPU). After such a silence the limiter must continue from what is
// applied, as after a reconnect, or the next write would jump. The same holds when enable and
// homed come back: a controller may ignore offset changes while disabled (LinuxCNC drops them
// while the machine is off or not homed, and zeroes its offsets at machine-on), so the ramp this
// loop wrote meanwhile may never have been applied. Only then: while the loop writes every cycle
// a read-back that disagrees is more likely frozen registers than a PLC acting on its own, and
// following it would make the written offsets jump. A departure within one limiter step is
// rounding or lag and keeps the limiter's state (its velocity matters for the acceleration
// limit).
void CompensationLoop::followController(time_point now, bool resumed) noexcept {
  const auto silence = now - lastWriteTime_;
  if (silence <= 2 * settings_.period && !(resumed && settings_.offsetReadback)) return;
  std::array<double, 3> applied{};
  if (settings_.offsetReadback) {
    if (!sample_.hasAppliedOffsets || !allFinite(sample_.appliedOffsetMm)) return;
    // A life counter that did not move says the registers, the read-back included, are old.
    if (sample_.hasSequence && sample_.sequence == lastSequence_) return;
    applied = sample_.appliedOffsetMm;
    const double toleranceMm =
        settings_.limiter.maxRateMmS * seconds(settings_.period) + kReadbackResolutionMm;
    bool departed = false;
    for (int k = 0; k < 3; ++k) {
      if (std::abs(applied[k] - limiter_.offsetMm[k]) > toleranceMm) departed = true;
    }
    if (!departed) return;
  } else if (settings_.plcZeroAfter.count() <= 0 || silence < settings_.plcZeroAfter) {
    return;  // not silent long enough for the PLC to have zeroed the offsets
  }
  resetLimiter(limiter_, applied);
  command_.offsetMm = limiter_.offsetMm;
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

void CompensationLoop::writeCommand(time_point now, std::uint16_t status,
                                    CycleReport& report) noexcept {
  command_.status = status;
  ++command_.heartbeat;
  const std::error_code ec = port_.write(command_);
  if (!ec) {
    ++counters_.writes;
    lastWriteTime_ = now;
    lastWriteFailed_ = false;
    report.wrote = true;
    return;
  }
  report.error = ec;
  if (isLinkError(ec)) {
    enterLinkLost(now, report);
  } else {
    ++counters_.writeErrors;
    lastWriteFailed_ = true;
  }
}

CycleReport CompensationLoop::step() noexcept {
  const time_point now = clock_.now();
  CycleReport report;
  report.previous = state_;
  ++counters_.cycles;

  const auto finish = [&]() noexcept {
    state_ = LoopState::Finished;
    report.state = state_;
    return report;
  };
  if (state_ == LoopState::Finished) return finish();

  if (!port_.connected()) {
    // Nothing can be written without the link; the PLC drops the offsets on the stalled
    // heartbeat, so a stop does not wait for a reconnection.
    if (stopRequested_) return finish();
    // The driver closed the link between cycles: same as a link error (counted, backoff).
    if (everConnected_ && state_ != LoopState::LinkLost) enterLinkLost(now, report);
    if (!tryConnect(now, report)) {
      report.state = state_;
      return report;
    }
  }

  const std::error_code readError = port_.read(sample_);
  if (readError) {
    report.error = readError;
    if (isLinkError(readError)) {
      enterLinkLost(now, report);
      return stopRequested_ ? finish() : report;
    }
    ++counters_.readErrors;
  }

  const bool wasSynced = synced_;
  if (!synced_) {
    if (readError || !synchronise(now)) {
      // Starting: write nothing until the applied offsets are known.
      if (stopRequested_) return finish();
      state_ = LoopState::Starting;
      report.state = state_;
      report.fault = fault_;
      return report;
    }
  }

  if (wasSynced && !readError) {
    const bool resumed = state_ == LoopState::Disabled && sample_.enable && sample_.homed;
    followController(now, resumed);
  }

  std::array<double, 3> target{};
  FaultCode fault = FaultCode::None;
  bool outOfTravel = false;
  LoopState next = LoopState::Active;

  if (stopRequested_) {
    if (state_ != LoopState::Stopping) {
      double worst = 0.0;
      for (double o : limiter_.offsetMm) worst = std::max(worst, std::abs(o));
      double rampS = worst / settings_.limiter.maxRateMmS;
      if (settings_.limiter.maxAccelMmS2 > 0.0) {
        rampS += 2.0 * settings_.limiter.maxRateMmS / settings_.limiter.maxAccelMmS2;
      }
      // Twice the ramp time plus a second: enough for the ramp with a few failed writes, and
      // bounded, so that a controller refusing writes cannot hold the shutdown.
      stopDeadline_ = now + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                std::chrono::duration<double>(2.0 * rampS + 1.0));
    }
    next = LoopState::Stopping;
  } else if (readError || lastWriteFailed_) {
    fault = FaultCode::TransactionError;
  } else {
    std::array<double, 3> q{};
    fault = checkInputs(now, q, outOfTravel);
    if (fault == FaultCode::None) {
      if (!sample_.enable || !sample_.homed) {
        next = LoopState::Disabled;
      } else {
        const model::Directions& directions = tracker_.update(q);
        const ModelOffset result = model_->offset(q, directions);
        if (result.clampedAxes != 0) outOfTravel = true;
        if (!allFinite(result.offsetMm)) {
          fault = FaultCode::ModelInvalid;
        } else if (!result.converged) {
          fault = FaultCode::NotConverged;
        } else {
          target = result.offsetMm;
        }
      }
    }
  }
  if (fault != FaultCode::None) next = LoopState::Fault;

  const LimiterState before = limiter_;
  const LimiterOutput out =
      limitStep(settings_.limiter, limiter_, target, seconds(settings_.period));
  if (out.invalidTarget && fault == FaultCode::None) {
    fault = FaultCode::ModelInvalid;
    next = LoopState::Fault;
  }
  command_.offsetMm = out.offsetMm;

  std::uint16_t status = 0;
  switch (next) {
    case LoopState::Active:
      status |= status::kActive;
      break;
    case LoopState::Disabled:
      status |= status::kDisabled;
      break;
    case LoopState::Fault:
      status = withFaultCode(status::kFault, fault);
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
  if (outOfTravel) status |= status::kOutOfTravel;
  if (now < reloadedUntil_) status |= status::kModelReloaded;
  if (reloadFailed_) status |= status::kReloadFailed;
  const bool lastOfStop = next == LoopState::Stopping && limiterAtZero(limiter_);
  if (lastOfStop) status = 0;  // zero offsets, status inactive

  if (fault != FaultCode::None) ++counters_.faultCycles;
  fault_ = fault;
  state_ = next;
  report.fault = fault;
  writeCommand(now, status, report);
  if (!report.wrote) {
    // The controller kept the previous value; continue the ramp from there, not from ours.
    limiter_ = before;
    command_.offsetMm = before.offsetMm;
  }
  if (state_ == LoopState::Stopping && ((lastOfStop && report.wrote) || now >= stopDeadline_)) {
    return finish();
  }
  report.state = state_;
  report.goodCycle = report.wrote && fault == FaultCode::None &&
                     (state_ == LoopState::Active || state_ == LoopState::Disabled);
  return report;
}

}  // namespace volcomp::loop
