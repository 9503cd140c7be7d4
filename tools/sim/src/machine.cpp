#include "volcomp/sim/machine.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "volcomp/loop/compensation_loop.hpp"

namespace volcomp::sim {
namespace {

constexpr std::array<const char*, 3> kAxes{"X", "Y", "Z"};
constexpr double kForever = std::numeric_limits<double>::infinity();
// The reversal transient: this many writer cycles after an axis reversed.
constexpr double kReversalWindowCycles = 3.0;

double until(double tS, double durationS) noexcept {
  return durationS > 0.0 ? tS + durationS : kForever;
}

double rmsUm(double sumSq, std::uint64_t n) noexcept {
  return n == 0 ? 0.0 : std::sqrt(sumSq / static_cast<double>(n)) * 1000.0;
}

}  // namespace

void ErrorStatistics::add(const Vec3& e) noexcept {
  ++samples;
  const double n2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  sumSqNorm += n2;
  maxNorm = std::max(maxNorm, std::sqrt(n2));
  for (std::size_t k = 0; k < 3; ++k) {
    sumSqAxis[k] += e[k] * e[k];
    maxAbsAxis[k] = std::max(maxAbsAxis[k], std::abs(e[k]));
  }
}

Machine::Machine(Path path, ErrorFunction trueError, MachineOptions options)
    : path_(std::move(path)), trueError_(std::move(trueError)), options_(options) {
  applied_ = options_.initialOffsetMm;
  enable_ = options_.enable;
  homed_ = options_.homed;
  programmed_ = path_.at(0.0);
}

void Machine::advanceLocked(double tS) {
  if (!started_) {
    started_ = true;
    lastT_ = tS;
    // The PLC's watchdog counts from power-up: offsets left applied without a daemon are removed
    // too, whoever set them.
    lastHeartbeatChangeT_ = tS;
  }
  const double dt = tS - lastT_;
  if (dt <= 0.0) return;
  // Feed hold: the path time stops for the part of dt inside the hold.
  // hold() advances the machine first, so a hold always starts at lastT_ or earlier.
  double moving = dt;
  if (activeAt(holdUntil_, tS)) {
    moving = 0.0;
  } else if (lastT_ < holdUntil_) {
    moving = tS - holdUntil_;
  }
  pathTimeS_ += moving;
  const Vec3 previous = programmed_;
  programmed_ = path_.at(pathTimeS_);
  for (std::size_t k = 0; k < 3; ++k) {
    const int before = directions_[k];
    if (programmed_[k] > previous[k]) directions_[k] = 1;
    if (programmed_[k] < previous[k]) directions_[k] = -1;
    if (before != 0 && directions_[k] != before) lastReversalT_ = tS;
  }
  if (options_.heartbeatTimeoutS > 0.0 && tS - lastHeartbeatChangeT_ > options_.heartbeatTimeoutS) {
    if (!watchdogTripped_) {
      watchdogTripped_ = true;
      ++watchdogTrips_;
    }
    // The controller removes the offsets itself, at its own rate (like Siemens CORR_VELO).
    const double step = options_.watchdogRampMmS * dt;
    for (auto& o : applied_) {
      const double before = o;
      o = o > 0.0 ? std::max(0.0, o - step) : std::min(0.0, o + step);
      if (o != before) controllerChanged_ = true;
    }
  }
  lastT_ = tS;
  if (options_.axisLatencyS > 0.0 &&
      (appliedHistory_.empty() || appliedHistory_.back().second != applied_)) {
    appliedHistory_.emplace_back(tS, applied_);
  }
}

// The offset acting at the axes: what was applied axisLatencyS ago.
Vec3 Machine::atAxesLocked(double tS) {
  if (!(options_.axisLatencyS > 0.0)) return applied_;
  if (appliedHistory_.empty() || appliedHistory_.back().second != applied_) {
    appliedHistory_.emplace_back(tS, applied_);
  }
  const double then = tS - options_.axisLatencyS;
  while (appliedHistory_.size() > 1 && appliedHistory_[1].first <= then) {
    appliedHistory_.pop_front();
  }
  return appliedHistory_.front().first <= then ? appliedHistory_.front().second
                                               : options_.initialOffsetMm;
}

loop::AxisSample Machine::inputs(double tS) {
  std::lock_guard lock(mutex_);
  advanceLocked(tS);
  ++sequence_;
  if (activeAt(freezeUntil_, tS)) {
    loop::AxisSample s = frozenSample_;
    s.enable = enable_;
    s.homed = homed_;
    s.faultAck = faultAck_;
    return s;
  }
  loop::AxisSample s;
  const Vec3 atAxes = atAxesLocked(tS);
  // A scan latches the positions: those of the last scan boundary (the path that far back,
  // unless a feed hold stopped it meanwhile).
  double latchS = tS;
  Vec3 programmed = programmed_;
  if (options_.positionScanS > 0.0) {
    latchS = std::floor(tS / options_.positionScanS) * options_.positionScanS;
    if (!activeAt(holdUntil_, tS)) programmed = path_.at(std::max(0.0, pathTimeS_ - (tS - latchS)));
  }
  for (std::size_t k = 0; k < 3; ++k) {
    s.positionMm[k] = options_.semantics == loop::PositionSemantics::Actual
                          ? programmed[k] + atAxes[k]
                          : programmed[k];
  }
  if (options_.timestampTickS > 0.0) {
    s.hasTimestamp = true;
    s.timestampTickS = options_.timestampTickS;
    s.timestampTicks = static_cast<std::uint16_t>(
        static_cast<std::uint64_t>(std::llround(latchS / options_.timestampTickS)) & 0xFFFFU);
  }
  s.enable = enable_;
  s.homed = homed_;
  s.hasAppliedOffsets = true;
  s.appliedOffsetMm = applied_;
  s.hasSequence = true;
  s.sequence = sequence_;
  // A garbled reply (or a controller reporting nonsense) in the X read-back; what it applies is
  // unchanged.
  if (activeAt(garbleUntil_, tS)) s.appliedOffsetMm[0] = garbleMm_;
  s.hasFaultAck = true;
  s.faultAck = faultAck_;
  frozenSample_ = s;
  return s;
}

void Machine::onSessionStart(double tS) {
  std::lock_guard lock(mutex_);
  advanceLocked(tS);
  ++sessions_;
}

void Machine::onWrite(double tS, const loop::OffsetCommand& command, bool partial) {
  std::lock_guard lock(mutex_);
  advanceLocked(tS);
  WriteRecord rec;
  rec.timeS = tS;
  rec.offsetMm = command.offsetMm;
  rec.status = command.status;
  rec.heartbeat = command.heartbeat;
  rec.partial = partial;
  if (partial) ++partialWrites_;
  // The reference of the rate check is what the controller applies right now (after any
  // watchdog ramp), and the time is the controller's: since the previous write it applied,
  // capped at one cycle (the daemon's dt is capped so: a gap allows one cycle's step, and a late
  // cycle followed by an on-time one may not put two steps into one period). When the controller
  // changed the offsets itself since the last write, the daemon follows that only once they
  // depart from its own by more than a step plus the read-back resolution (docs/daemon.md), so
  // that much more is allowed then.
  const Limits& lim = options_.limits;
  const double windowS = anyWrite_ ? std::clamp(tS - lastWriteT_, 0.0, lim.cycleS) : lim.cycleS;
  for (std::size_t k = 0; k < 3; ++k) {
    const double o = command.offsetMm[k];
    const double q = lim.quantumMm[k];
    const double stepMm = lim.maxRateMmS[k] * (windowS + lim.rateToleranceS);
    const double allowedMm = controllerChanged_
                                 ? stepMm + lim.maxRateMmS[k] * (lim.cycleS + lim.rateToleranceS) +
                                       loop::kReadbackResolutionMm
                                 : stepMm;
    std::string what;
    if (!std::isfinite(o)) {
      what = "not finite";
    } else if (std::abs(o) > lim.maxOffsetMm[k] + q + 1e-9) {
      what = "|offset| " + std::to_string(o) + " mm > max_offset " +
             std::to_string(lim.maxOffsetMm[k]);
      ++offsetViolations_;
    } else if (std::abs(o - applied_[k]) > allowedMm + 2.0 * q + 1e-9) {
      what = "step " + std::to_string(o - applied_[k]) + " mm from the applied " +
             std::to_string(applied_[k]) + " mm > " + std::to_string(allowedMm) + " mm (max_rate " +
             std::to_string(lim.maxRateMmS[k]) + " mm/s over " + std::to_string(windowS) +
             " s since the previous write, cycle " + std::to_string(lim.cycleS) + " s)";
      ++rateViolations_;
    }
    if (!what.empty()) {
      rec.violation = true;
      ++axisViolations_[k];
      if (firstViolation_.empty()) {
        std::ostringstream msg;
        msg << "t=" << tS << " s axis " << kAxes[k] << ": " << what;
        firstViolation_ = msg.str();
      }
    }
    if (std::isfinite(o)) maxAbsWrittenMm_[k] = std::max(maxAbsWrittenMm_[k], std::abs(o));
  }
  if (rec.violation) ++violations_;
  // A controller takes what it is given (that is why the daemon limits it); non-finite values
  // are refused by any real controller's range check.
  for (std::size_t k = 0; k < 3; ++k) {
    if (std::isfinite(command.offsetMm[k])) applied_[k] = command.offsetMm[k];
  }
  if (!anyWrite_) {
    anyWrite_ = true;
    firstWriteT_ = tS;
    lastHeartbeatChangeT_ = tS;
    lastHeartbeat_ = command.heartbeat;
  } else if (command.heartbeat != lastHeartbeat_) {
    lastHeartbeat_ = command.heartbeat;
    lastHeartbeatChangeT_ = tS;
    watchdogTripped_ = false;
  }
  if (options_.axisLatencyS > 0.0) appliedHistory_.emplace_back(tS, applied_);
  controllerChanged_ = false;
  lastWriteT_ = tS;
  ++writeCount_;
  if (options_.keepWrites) writes_.push_back(rec);
}

TransportFault Machine::transportFault(double tS) {
  std::lock_guard lock(mutex_);
  TransportFault f;
  f.stall = activeAt(stallUntil_, tS);
  f.linkDown = activeAt(dropUntil_, tS);
  f.exceptionCode = activeAt(exceptionUntil_, tS) ? exceptionCode_ : 0;
  return f;
}

void Machine::countRequest(bool answered, bool exception) {
  std::lock_guard lock(mutex_);
  ++requests_;
  if (!answered) ++unanswered_;
  if (exception) ++exceptionsSent_;
}

WriteReply Machine::takeWriteReply() {
  std::lock_guard lock(mutex_);
  WriteReply r;
  if (droppedReplies_ > 0) {
    --droppedReplies_;
    ++repliesDropped_;
    r.drop = true;
  } else if (lateReplies_ > 0) {
    --lateReplies_;
    ++lateRepliesSent_;
    r.delayS = lateReplyS_;
  }
  return r;
}

ClientPause Machine::takeClientPause() {
  std::lock_guard lock(mutex_);
  const ClientPause p = pause_;
  if (p.pid != 0) ++clientPauses_;
  pause_ = {};
  return p;
}

void Machine::sample(double tS) {
  std::lock_guard lock(mutex_);
  advanceLocked(tS);
  if (!anyWrite_ || tS < firstWriteT_ + options_.settleS) return;
  const Vec3 q = programmed_;
  const Vec3 e = trueError_(q, directions_);
  const Vec3 atAxes = atAxesLocked(tS);
  Vec3 moved{};
  for (std::size_t k = 0; k < 3; ++k) moved[k] = q[k] + atAxes[k];
  const Vec3 em = trueError_(moved, directions_);
  Vec3 comp{};
  for (std::size_t k = 0; k < 3; ++k) comp[k] = em[k] + atAxes[k];
  uncompensated_.add(e);
  compensated_.add(comp);
  // The ideal offset at this instant: o* = -E(q + o*) (the daemon's solve with the true model,
  // at the true position and direction, zero latency); the fixed point converges at once, E
  // changing by far less than a micrometre per micrometre. What the applied offset leaves beyond
  // what o* would leave is the motion-induced error.
  Vec3 ideal{};
  for (int iteration = 0; iteration < 4; ++iteration) {
    Vec3 at{};
    for (std::size_t k = 0; k < 3; ++k) at[k] = q[k] + ideal[k];
    const Vec3 ei = trueError_(at, directions_);
    for (std::size_t k = 0; k < 3; ++k) ideal[k] = -ei[k];
  }
  Vec3 at{};
  for (std::size_t k = 0; k < 3; ++k) at[k] = q[k] + ideal[k];
  const Vec3 ei = trueError_(at, directions_);
  Vec3 motion{};
  for (std::size_t k = 0; k < 3; ++k) motion[k] = comp[k] - (ei[k] + ideal[k]);
  motion_.add(motion);
  // Steady motion is what lies more than the window away from every reversal: after one until the
  // daemon has read it, decided and written; before one where it predicted the turn.
  const double window = kReversalWindowCycles * options_.limits.cycleS;
  if (lastReversalT_ > lastSampleT_) {
    while (!steadyPending_.empty() && steadyPending_.back().first > lastReversalT_ - window) {
      steadyPending_.pop_back();
    }
  }
  lastSampleT_ = tS;
  while (!steadyPending_.empty() && steadyPending_.front().first < tS - window) {
    motionSteady_.add(steadyPending_.front().second);
    steadyPending_.pop_front();
  }
  if (!(tS - lastReversalT_ < window)) steadyPending_.emplace_back(tS, motion);
}

void Machine::stall(double tS, double durationS) {
  std::lock_guard lock(mutex_);
  stallUntil_ = until(tS, durationS);
}
void Machine::dropLink(double tS, double durationS) {
  std::lock_guard lock(mutex_);
  dropUntil_ = until(tS, durationS);
}
void Machine::exception(double tS, int code, double durationS) {
  std::lock_guard lock(mutex_);
  exceptionCode_ = code;
  exceptionUntil_ = until(tS, durationS);
}
void Machine::freeze(double tS, double durationS) {
  std::lock_guard lock(mutex_);
  freezeUntil_ = until(tS, durationS);
}
void Machine::hold(double tS, double durationS) {
  std::lock_guard lock(mutex_);
  advanceLocked(tS);
  holdUntil_ = until(tS, durationS);
}
void Machine::setEnable(bool on) {
  std::lock_guard lock(mutex_);
  enable_ = on;
}
void Machine::setHomed(bool on) {
  std::lock_guard lock(mutex_);
  homed_ = on;
}
void Machine::garbleReadback(double tS, double mm, double durationS) {
  std::lock_guard lock(mutex_);
  garbleMm_ = mm;
  garbleUntil_ = until(tS, durationS);
}
void Machine::setFaultAck(bool on) {
  std::lock_guard lock(mutex_);
  faultAck_ = on;
}
void Machine::lateReplies(double delayS, int count) {
  std::lock_guard lock(mutex_);
  lateReplyS_ = delayS;
  lateReplies_ = count;
}
void Machine::dropReplies(int count) {
  std::lock_guard lock(mutex_);
  droppedReplies_ = count;
}
void Machine::pauseClient(int pid, double seconds) {
  std::lock_guard lock(mutex_);
  pause_ = {pid, seconds};
}
void Machine::resume() {
  std::lock_guard lock(mutex_);
  stallUntil_ = dropUntil_ = exceptionUntil_ = freezeUntil_ = holdUntil_ = garbleUntil_ = 0.0;
  lateReplies_ = droppedReplies_ = 0;
  pause_ = {};
}

std::vector<WriteRecord> Machine::writes() const {
  std::lock_guard lock(mutex_);
  return writes_;
}
Vec3 Machine::appliedOffsetMm() const {
  std::lock_guard lock(mutex_);
  return applied_;
}
Vec3 Machine::programmedPositionMm() const {
  std::lock_guard lock(mutex_);
  return programmed_;
}

nlohmann::json Machine::report(double tS) const {
  std::lock_guard lock(mutex_);
  using nlohmann::json;
  // The samples of the last window: steady as far as anybody knows at the end of the run.
  ErrorStatistics motionSteady = motionSteady_;
  for (const auto& pending : steadyPending_) motionSteady.add(pending.second);
  json axes = json::object();
  for (std::size_t k = 0; k < 3; ++k) {
    axes[kAxes[k]] = {
        {"rms_uncompensated_um", rmsUm(uncompensated_.sumSqAxis[k], uncompensated_.samples)},
        {"rms_compensated_um", rmsUm(compensated_.sumSqAxis[k], compensated_.samples)},
        {"max_uncompensated_um", uncompensated_.maxAbsAxis[k] * 1000.0},
        {"max_compensated_um", compensated_.maxAbsAxis[k] * 1000.0},
        {"rms_motion_um", rmsUm(motion_.sumSqAxis[k], motion_.samples)},
        {"limiter_violations", axisViolations_[k]},
        {"max_abs_offset_written_mm", maxAbsWrittenMm_[k]},
    };
  }
  return json{
      {"duration_s", tS},
      {"samples", compensated_.samples},
      {"writes", writeCount_},
      {"partial_writes", partialWrites_},
      {"limiter_violations", violations_},
      {"offset_violations", offsetViolations_},
      {"rate_violations", rateViolations_},
      {"first_violation", firstViolation_},
      {"rms_uncompensated_um", rmsUm(uncompensated_.sumSqNorm, uncompensated_.samples)},
      {"rms_compensated_um", rmsUm(compensated_.sumSqNorm, compensated_.samples)},
      {"max_uncompensated_um", uncompensated_.maxNorm * 1000.0},
      {"max_compensated_um", compensated_.maxNorm * 1000.0},
      {"rms_motion_um", rmsUm(motion_.sumSqNorm, motion_.samples)},
      {"max_motion_um", motion_.maxNorm * 1000.0},
      {"rms_motion_steady_um", rmsUm(motionSteady.sumSqNorm, motionSteady.samples)},
      {"max_motion_steady_um", motionSteady.maxNorm * 1000.0},
      {"motion_steady_samples", motionSteady.samples},
      {"axes", axes},
      {"applied_offset_mm", applied_},
      {"sessions", sessions_},
      {"requests", requests_},
      {"requests_unanswered", unanswered_},
      {"exceptions_sent", exceptionsSent_},
      {"late_replies", lateRepliesSent_},
      {"replies_dropped", repliesDropped_},
      {"client_pauses", clientPauses_},
      {"watchdog_trips", watchdogTrips_},
      {"position_semantics",
       options_.semantics == loop::PositionSemantics::Actual ? "actual" : "commanded"},
  };
}

}  // namespace volcomp::sim
