#include "volcomp/daemon/daemon.hpp"

#include <spdlog/spdlog.h>
#include <time.h>

#include <asio/post.hpp>
#include <exception>
#include <utility>

#include "volcomp/config/config_error.hpp"

namespace volcomp::daemon {

using loop::CycleReport;
using loop::FaultCode;
using loop::LoopState;

namespace {

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
      loop_(port, clock, std::move(initial.model), loopSettingsFrom(config_)),
      scheduler_(clock, loopSettingsFrom(config_).period, [this] { return cycle(); }),
      reloadLoader_(std::move(reloadLoader)),
      onFinished_(std::move(onFinished)) {}

Daemon::~Daemon() {
  if (reloadThread_.joinable()) reloadThread_.join();
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
  if (reloading_) {
    spdlog::warn("reload requested while one is in progress; ignored");
    return;
  }
  if (stopping_) return;
  reloading_ = true;
  spdlog::info("reloading configuration and model");
  notifier_.notify("RELOADING=1\nMONOTONIC_USEC=" + monotonicUsec());
  if (reloadThread_.joinable()) reloadThread_.join();
  reloadThread_ = std::thread([this] {
    std::shared_ptr<LoadedConfiguration> loaded;
    std::string error;
    try {
      loaded = std::make_shared<LoadedConfiguration>(reloadLoader_());
    } catch (const std::exception& e) {
      error = e.what();
    }
    asio::post(io_, [this, loaded, error] { finishReload(loaded, error); });
  });
}

void Daemon::finishReload(std::shared_ptr<LoadedConfiguration> loaded, std::string error) {
  if (reloadThread_.joinable()) reloadThread_.join();
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
    loop_.setSettings(loopSettingsFrom(next));
    loop_.setModel(loaded->model);
    spdlog::set_level(levelFromName(next.logLevel));
    spdlog::info("reloaded: model '{}' from {}", loaded->model->name(), next.modelPath);
    // Keep what only a restart changes, so that later messages compare against what runs.
    next.cyclePeriodMs = config_.cyclePeriodMs;
    next.transport = config_.transport;
    next.offsetReadback = config_.offsetReadback;
    next.plcZeroAfterMs = config_.plcZeroAfterMs;
    config_ = std::move(next);
    reloadError_.clear();
  }
  // A reload ends with READY=1 either way: the service keeps running.
  if (ready_) notifier_.notify("READY=1");
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
  if (report.goodCycle && !ready_) {
    ready_ = true;
    notifier_.notify("READY=1");
    spdlog::info("ready: first good cycle");
  }
  const loop::Clock::time_point now = clock_.now();
  if (report.state == LoopState::Finished) {
    finished_ = true;
    notifier_.notify("STATUS=stopped");
    spdlog::info("stopped after {} cycles ({} overruns); latest start {} us after its deadline",
                 loop_.counters().cycles, scheduler_.overruns(),
                 std::chrono::duration_cast<std::chrono::microseconds>(scheduler_.maxWakeLateness())
                     .count());
    if (onFinished_) asio::post(io_, onFinished_);
    return false;
  }
  notifyPeriodic(now);
  return true;
}

void Daemon::logReport(const CycleReport& report) {
  lastLoggedFault_ = report.fault;
  const std::string_view from = loop::stateName(report.previous);
  const std::string_view to = loop::stateName(report.state);
  const std::string error = report.error ? report.error.message() : std::string();
  switch (report.state) {
    case LoopState::Fault:
      spdlog::warn("{} -> fault: {}{}{}", from, loop::faultName(report.fault),
                   error.empty() ? "" : ": ", error);
      break;
    case LoopState::LinkLost:
      spdlog::warn("{} -> link lost to {}{}{}; reconnecting with backoff", from,
                   config::transportEndpoint(config_.transport), error.empty() ? "" : ": ", error);
      break;
    case LoopState::Starting:
      if (report.fault != FaultCode::None) {
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
  if (!reloadError_.empty()) line += ", reload failed: " + reloadError_;
  // One line: a newline would start a new sd_notify assignment.
  for (char& c : line) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return line;
}

void Daemon::notifyPeriodic(loop::Clock::time_point now) {
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
