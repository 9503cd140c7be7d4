#include "volcomp/daemon/daemon.hpp"

#include <sched.h>

#include <spdlog/spdlog.h>
#include <time.h>

#include <asio/post.hpp>
#include <exception>
#include <thread>
#include <utility>

#include "volcomp/config/config_error.hpp"
#include "volcomp/daemon/limit_changes.hpp"

namespace volcomp::daemon {

using loop::CycleReport;
using loop::FaultCode;
using loop::LoopState;

namespace {

std::int64_t microseconds(std::chrono::nanoseconds d) {
  return std::chrono::duration_cast<std::chrono::microseconds>(d).count();
}

spdlog::level::level_enum levelFromName(const std::string& name) {
  return spdlog::level::from_str(name);
}

std::string monotonicUsec() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return std::to_string(static_cast<std::uint64_t>(ts.tv_sec) * 1000000u +
                        static_cast<std::uint64_t>(ts.tv_nsec) / 1000u);
}

}  // namespace

Daemon::Daemon(asio::io_context& io, loop::ControllerPort& port, WaitableClock& clock,
               Notifier& notifier, LoadedConfiguration initial, Loader reloadLoader,
               std::function<void()> onFinished)
    : io_(io),
      clock_(clock),
      notifier_(notifier),
      config_(std::move(initial.config)),
      startWarnings_(std::move(initial.warnings)),
      loop_(port, clock, std::move(initial.model), loopSettingsFrom(config_)),
      scheduler_(clock, loopSettingsFrom(config_).period, [this] { return cycle(); }),
      reloadLoader_(std::move(reloadLoader)),
      onFinished_(std::move(onFinished)) {}

Daemon::~Daemon() {
  abandonReload();
}

// A reload's helper thread is detached: a load blocked on file I/O (a hung mount, a FIFO as the
// model path) must never hold a stop or the next reload. Once abandoned it hands nothing back;
// whatever it loads is dropped when it finishes, if ever.
void Daemon::abandonReload() {
  if (!reload_) return;
  std::lock_guard lock(reload_->mutex);
  reload_->abandoned = true;
  reload_.reset();
}

void Daemon::start() {
  watchdog_ = notifier_.watchdogInterval();
  startTime_ = clock_.now();
  lastStatus_ = startTime_;
  spdlog::info(
      "starting volcompd {}: model '{}', transport {}, cycle {} ms, position semantics {}",
      VOLCOMP_VERSION, loop_.model().name(), config::transportEndpoint(config_.transport),
      config_.cyclePeriodMs,
      config_.positionSemantics == loop::PositionSemantics::Actual ? "actual" : "commanded");
  for (const std::string& warning : startWarnings_) spdlog::warn("{}", warning);
  if (const std::string advice = realtimeAdvice(scheduler_.period(), sched_getscheduler(0));
      !advice.empty()) {
    spdlog::warn("{}", advice);
  }
  scheduler_.start();
}

void Daemon::requestStop() {
  if (stopping_ || finished_) return;
  stopping_ = true;
  spdlog::info("stop requested: ramping the offsets out");
  notifier_.notify("STOPPING=1");
  loop_.requestStop();
  if (!scheduler_.running()) {
    finished_ = true;
    if (onFinished_) onFinished_();
  }
}

void Daemon::requestReload() {
  if (stopping_) return;
  if (reloading_) {
    reloadAgain_ = true;
    spdlog::warn(
        "reload requested while one is in progress (for {:.1f} s): it follows that one",
        std::chrono::duration<double>(std::chrono::steady_clock::now() - reloadStarted_).count());
    return;
  }
  reloading_ = true;
  reloadAgain_ = false;
  reloadStarted_ = std::chrono::steady_clock::now();
  spdlog::info("reloading configuration and model");
  notifier_.notify("RELOADING=1\nMONOTONIC_USEC=" + monotonicUsec());
  auto job = std::make_shared<ReloadJob>();
  reload_ = job;
  std::thread([job, loader = reloadLoader_, io = &io_, this] {
    std::shared_ptr<LoadedConfiguration> loaded;
    std::string error;
    try {
      loaded = std::make_shared<LoadedConfiguration>(loader());
    } catch (const std::exception& e) {
      error = e.what();
    }
    std::lock_guard lock(job->mutex);
    if (job->abandoned) return;
    asio::post(*io, [this, job, loaded, error] {
      if (!job->abandoned) finishReload(loaded, error);
    });
  }).detach();
}

// A reload that has not finished after reloadTimeout_ is given up (its thread may be blocked on
// file I/O for ever): the running model stays, RELOAD_FAILED is set, and reloads work again.
void Daemon::checkReloadTimeout() {
  if (!reloading_ || std::chrono::steady_clock::now() - reloadStarted_ < reloadTimeout_) return;
  abandonReload();
  finishReload(nullptr,
               fmt::format("not finished after {:.1f} s (a file blocked on I/O?); abandoned",
                           std::chrono::duration<double>(reloadTimeout_).count()));
}

void Daemon::finishReload(std::shared_ptr<LoadedConfiguration> loaded, std::string error) {
  reload_.reset();
  reloading_ = false;
  if (!loaded) {
    reloadError_ = error.empty() ? std::string("unknown error") : error;
    loop_.noteReloadFailed();
    spdlog::error("reload rejected, keeping the running model: {}", reloadError_);
  } else {
    config::DaemonConfig& next = loaded->config;
    if (next.cyclePeriodMs != config_.cyclePeriodMs) {
      spdlog::warn("cycle_period_ms changed ({} -> {} ms): takes effect on restart",
                   config_.cyclePeriodMs, next.cyclePeriodMs);
    }
    if (next.transport != config_.transport) {
      spdlog::warn("transport section changed: takes effect on restart");
    }
    if (next.offsetReadback != config_.offsetReadback ||
        next.plcZeroAfterMs != config_.plcZeroAfterMs) {
      spdlog::warn("offset_readback/plc_zero_after_ms changed: take effect on restart");
    }
    const LimitChangeLines limits =
        describeLimitChanges(loop_.settings().limiter, next.limiter, next.file);
    loop_.setSettings(loopSettingsFrom(next));
    loop_.setModel(loaded->model);
    spdlog::set_level(levelFromName(next.logLevel));
    spdlog::info("reloaded: model '{}' from {}", loaded->model->name(), next.modelPath);
    for (const std::string& line : limits.tightened) spdlog::info("{}", line);
    for (const std::string& line : limits.widened) spdlog::warn("{}", line);
    for (const std::string& warning : loaded->warnings) spdlog::warn("{}", warning);
    // Keep what only a restart changes, so that later messages compare against what runs: the
    // limits the loop took (a widened one stays at its running value until a restart).
    next.limiter = loop_.settings().limiter;
    next.cyclePeriodMs = config_.cyclePeriodMs;
    next.transport = config_.transport;
    next.offsetReadback = config_.offsetReadback;
    next.plcZeroAfterMs = config_.plcZeroAfterMs;
    config_ = std::move(next);
    reloadError_.clear();
  }
  // A reload ends with READY=1 either way: the service keeps running.
  if (ready_) notifier_.notify("READY=1");
  if (reloadAgain_ && !stopping_) {
    reloadAgain_ = false;
    asio::post(io_, [this] { requestReload(); });
  }
}

bool Daemon::cycle() {
  const CycleReport report = loop_.step();
  if (report.stateChanged() || report.fault != lastLoggedFault_) {
    logReport(report);
  } else if (report.state == LoopState::LinkLost && report.error) {
    // At most one per backoff step (100 ms .. 2 s), so not a per-cycle line.
    spdlog::debug("reconnect to {} failed: {}", config::transportEndpoint(config_.transport),
                  report.error.message());
  }
  logEvents(report);
  if (report.goodCycle && !ready_) {
    ready_ = true;
    notifier_.notify("READY=1");
    spdlog::info("ready: first good cycle");
  }
  const loop::Clock::time_point now = clock_.now();
  if (report.state == LoopState::Finished) {
    finished_ = true;
    abandonReload();
    notifier_.notify("STATUS=stopped");
    spdlog::info(
        "stopped after {} cycles ({} overruns); {} late reads, {} unknown write "
        "outcomes; latest start {} us after its deadline, {} cycles started a period or more "
        "late, {} deadlines skipped ({} while a cycle ran), longest cycle {} us",
        loop_.counters().cycles, scheduler_.overruns(), loop_.counters().lateReads,
        loop_.counters().unknownOutcomes, microseconds(scheduler_.maxWakeLateness()),
        scheduler_.lateStarts(), scheduler_.missedDeadlines(), scheduler_.missedWhileRunning(),
        microseconds(scheduler_.longestCycle()));
    if (onFinished_) asio::post(io_, onFinished_);
    return false;
  }
  notifyPeriodic(now);
  return true;
}

// Events of a cycle that are not state changes, each logged once when it starts (never per
// cycle): a read-back outside the band and its return, the saturation warning, an acknowledged
// latch, the first write withheld in a row.
void Daemon::logEvents(const CycleReport& report) {
  logReadback(report);
  if (report.saturationAxis >= 0) {
    const auto k = static_cast<std::size_t>(report.saturationAxis);
    spdlog::warn(
        "limiter: the clamp has held axis {} for {:.1f} s: the model asks for {:+.4f} mm, "
        "max_offset_mm is {:.4f} (status SATURATED{})",
        "XYZ"[k], std::chrono::duration<double>(loop_.settings().saturationWarning).count(),
        report.saturationRequestedMm, loop_.settings().limiter.axes[k].maxOffsetMm,
        loop_.settings().saturationFault.count() > 0
            ? fmt::format("; fault sustained-limit after {:.1f} s",
                          std::chrono::duration<double>(loop_.settings().saturationFault).count())
            : std::string());
  }
  if (report.acknowledged) spdlog::info("latched fault acknowledged by the controller");
  if (report.unknownOutcome) {
    spdlog::debug("write failed on a live link ({}): the controller may have applied it",
                  report.error.message());
  }
  if (report.withheld != loop::Withheld::None && report.withheld != lastWithheld_ &&
      report.withheld != loop::Withheld::ReadbackOutOfRange) {
    spdlog::warn("cycle wrote nothing: {}", report.withheld == loop::Withheld::StaleRead
                                                ? "its reads were older than read_to_write_max_ms "
                                                  "when the write was due (process stopped or "
                                                  "starved, or a slow controller)"
                                                : "no value within one step of every value the "
                                                  "controller may apply after a failed write");
  }
  lastWithheld_ = report.withheld;
}

// The values that caused the fault, when they came, and the return into the band: once each,
// however often the fault itself is logged again (a latched fault interrupted by failed
// transactions, a reconnect), and never with the values of a later cycle.
void Daemon::logReadback(const CycleReport& report) const {
  if (report.readbackLeftBand) {
    const auto& o = report.readbackOutsideMm;
    const auto& limits = loop_.settings().limiter.axes;
    spdlog::warn(
        "applied offsets read back {:+.4f} {:+.4f} {:+.4f} mm, outside +-max_offset_mm ({:g} {:g} "
        "{:g} mm): nothing is written while they are (the controller's heartbeat watchdog removes "
        "them)",
        o[0], o[1], o[2], limits[0].maxOffsetMm, limits[1].maxOffsetMm, limits[2].maxOffsetMm);
  }
  if (report.readbackBackInBand) {
    const auto& o = loop_.lastSample().appliedOffsetMm;
    spdlog::info(
        "applied offsets read back inside +-max_offset_mm again ({:+.4f} {:+.4f} {:+.4f} "
        "mm): writing resumes from them{}",
        o[0], o[1], o[2],
        loop_.latchedFault() != FaultCode::None ? ", in fault until the controller acknowledges it"
                                                : "");
  }
}

void Daemon::logReport(const CycleReport& report) {
  lastLoggedFault_ = report.fault;
  const std::string_view from = loop::stateName(report.previous);
  const std::string_view to = loop::stateName(report.state);
  const std::string error = report.error ? report.error.message() : std::string();
  const char* latched = loop_.latchedFault() != FaultCode::None
                            ? " (latched: stays until the controller acknowledges it)"
                            : "";
  switch (report.state) {
    case LoopState::Fault:
      spdlog::warn("{} -> fault: {}{}{}{}", from, loop::faultName(report.fault),
                   error.empty() ? "" : ": ", error, latched);
      break;
    case LoopState::LinkLost:
      spdlog::warn("{} -> link lost to {}{}{}; reconnecting with backoff", from,
                   config::transportEndpoint(config_.transport), error.empty() ? "" : ": ", error);
      break;
    case LoopState::Starting:
      if (report.fault == FaultCode::ReadbackOutOfRange) {
        spdlog::warn("starting: {}: waiting for applied offsets inside +-max_offset_mm",
                     loop::faultName(report.fault));
      } else if (report.fault != FaultCode::None) {
        spdlog::warn("starting: applied offsets read back are invalid ({})",
                     loop::faultName(report.fault));
      } else {
        spdlog::info("{} -> starting: waiting for the applied offsets", from);
      }
      break;
    default:
      spdlog::info("{} -> {}", from, to);
      break;
  }
}

std::string Daemon::statusLine() const {
  const auto& o = loop_.lastOffsetMm();
  std::string line = fmt::format(
      "{} {:.1f} Hz, offsets {:+.4f} {:+.4f} {:+.4f} mm, fault {}, fault cycles {}, overruns {}, "
      "link losses {}, model '{}'",
      loop::stateName(loop_.state()), cycleRateHz_, o[0], o[1], o[2],
      loop::faultName(loop_.fault()), loop_.counters().faultCycles, scheduler_.overruns(),
      loop_.counters().linkLosses, loop_.model().name());
  if (loop_.latchedFault() != FaultCode::None) {
    line += fmt::format(", latched {} (acknowledge)", loop::faultName(loop_.latchedFault()));
  }
  const loop::LoopCounters& counts = loop_.counters();
  if (counts.unknownOutcomes + counts.lateReads + counts.withheldWrites > 0) {
    line += fmt::format(", unknown write outcomes {}, late reads {}, writes withheld {}",
                        counts.unknownOutcomes, counts.lateReads, counts.withheldWrites);
  }
  if (!reloadError_.empty()) line += ", reload failed: " + reloadError_;
  // One line: a newline would start a new sd_notify assignment.
  for (char& c : line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return line;
}

void Daemon::notifyPeriodic(loop::Clock::time_point now) {
  checkReloadTimeout();
  if (watchdog_ && now - lastWatchdog_ >= *watchdog_ / 4) {
    notifier_.notify("WATCHDOG=1");
    lastWatchdog_ = now;
  }
  const auto sinceStatus = now - lastStatus_;
  if (sinceStatus >= std::chrono::seconds(1)) {
    const std::uint64_t cycles = scheduler_.cycles();
    cycleRateHz_ = static_cast<double>(cycles - cyclesAtLastStatus_) /
                   std::chrono::duration<double>(sinceStatus).count();
    cyclesAtLastStatus_ = cycles;
    lastStatus_ = now;
    const std::uint64_t overruns = scheduler_.overruns();
    if (overruns != overrunsAtLastStatus_) {
      spdlog::warn("{} cycle overruns in the last {:.1f} s ({} deadlines skipped in total)",
                   overruns - overrunsAtLastStatus_,
                   std::chrono::duration<double>(sinceStatus).count(),
                   scheduler_.missedDeadlines());
      overrunsAtLastStatus_ = overruns;
    }
    const std::uint64_t lateReads = loop_.counters().lateReads;
    if (lateReads != lateReadsAtLastStatus_) {
      spdlog::warn(
          "{} late reads in the last {:.1f} s: a read was older than read_to_write_max_ms when its "
          "write was due (process stopped or starved, or a slow controller); read again",
          lateReads - lateReadsAtLastStatus_, std::chrono::duration<double>(sinceStatus).count());
      lateReadsAtLastStatus_ = lateReads;
    }
    notifier_.notify("STATUS=" + statusLine());
    if (loop_.state() == LoopState::Starting && loop_.settings().offsetReadback &&
        !warnedStarting_ && now - startTime_ >= std::chrono::seconds(5)) {
      warnedStarting_ = true;
      spdlog::warn(
          "still starting after 5 s: no applied offsets read back yet (reads failing, or no "
          "applied-offset registers mapped; without a read-back set offset_readback false and "
          "plc_zero_after_ms)");
    }
  }
}

}  // namespace volcomp::daemon
