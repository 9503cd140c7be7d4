#pragma once
/// The daemon around the loop: the periodic scheduler, service-manager notifications, state-change
/// logging, stop and reload. Everything runs on one io_context thread except the reload's file
/// loading and validation, which runs on a detached helper thread and hands its result back to
/// the io_context, so that a slow, failing or hung load never delays a cycle or a stop: a stop
/// abandons a reload in progress, and a reload not finished after kReloadTimeout is given up
/// (RELOAD_FAILED, the running model stays). A reload requested during another follows it.
///
/// Notifications: READY=1 after the first good cycle (and after each reload), WATCHDOG=1 from the
/// cycle itself at a quarter of the watchdog interval (a stuck cycle stops the pings),
/// STATUS=<summary> at most once per second, STOPPING=1 on stop, RELOADING=1 before a reload.
/// Logging happens on state changes, reloads and once per second for new overruns, never per
/// cycle.

#include <asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/daemon/configuration.hpp"
#include "volcomp/daemon/notifier.hpp"
#include "volcomp/daemon/scheduler.hpp"
#include "volcomp/daemon/waitable_clock.hpp"
#include "volcomp/loop/compensation_loop.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::daemon {

class Daemon {
 public:
  /// How long a reload may take before it is given up, in real (steady-clock) time: the load
  /// is file I/O on a helper thread, whatever clock the cycles run on.
  static constexpr std::chrono::seconds kReloadTimeout{10};

  /// Loads a configuration for a reload; throws on a bad file (the running one then stays).
  using Loader = std::function<LoadedConfiguration()>;

  /// `clock` is the one time source of the loop and the scheduler (and waits for the deadlines);
  /// it must run its waits on `io`.
  Daemon(asio::io_context& io, loop::ControllerPort& port, WaitableClock& clock, Notifier& notifier,
         LoadedConfiguration initial, Loader reloadLoader, std::function<void()> onFinished);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  void start();
  /// SIGTERM/SIGINT: ramp out, write zero and status inactive, then finish (onFinished).
  void requestStop();
  /// SIGHUP: load and validate config and model off the io_context thread, then take them over
  /// between cycles; a rejected file keeps everything as it was and sets RELOAD_FAILED. The
  /// limiter's limits only tighten: a wider one is logged (old -> new) and not taken, the running
  /// value stays until a restart; a narrower one is taken and logged (limit_changes.hpp).
  void requestReload();
  /// Runs a cycle now, on the io_context thread (a Modbus master completed a position set with
  /// cycle_trigger "write"); the period timer then runs one only when no such event came for a
  /// period. Ignored before start() and after the loop finished.
  void triggerCycle() { scheduler_.runNow(); }
  /// Overrides kReloadTimeout (tests).
  void setReloadTimeout(std::chrono::steady_clock::duration timeout) { reloadTimeout_ = timeout; }

  const loop::CompensationLoop& loop() const noexcept { return loop_; }
  const PeriodicScheduler& scheduler() const noexcept { return scheduler_; }
  bool ready() const noexcept { return ready_; }
  bool reloading() const noexcept { return reloading_; }
  /// The message of the last rejected reload (empty after a successful one).
  const std::string& reloadError() const noexcept { return reloadError_; }
  /// The one-line summary sent as STATUS=.
  std::string statusLine() const;

 private:
  bool cycle();
  void logReport(const loop::CycleReport& report);
  void logEvents(const loop::CycleReport& report);
  void logReadback(const loop::CycleReport& report) const;
  void notifyPeriodic(loop::Clock::time_point now);
  void finishReload(std::shared_ptr<LoadedConfiguration> loaded, std::string error);
  void checkReloadTimeout();
  void abandonReload();

  /// Shared with a reload's helper thread: set `abandoned` (under the mutex) and the thread
  /// hands nothing back.
  struct ReloadJob {
    std::mutex mutex;
    bool abandoned = false;
  };

  asio::io_context& io_;
  const loop::Clock& clock_;
  Notifier& notifier_;
  config::DaemonConfig config_;
  std::vector<std::string> startWarnings_;  // the initial model's, logged by start()
  loop::CompensationLoop loop_;
  PeriodicScheduler scheduler_;
  Loader reloadLoader_;
  std::function<void()> onFinished_;
  std::shared_ptr<ReloadJob> reload_;
  bool reloadAgain_ = false;
  std::chrono::steady_clock::time_point reloadStarted_{};
  std::chrono::steady_clock::duration reloadTimeout_ = kReloadTimeout;

  bool ready_ = false;
  bool stopping_ = false;
  bool reloading_ = false;
  bool finished_ = false;
  std::string reloadError_;
  std::optional<std::chrono::microseconds> watchdog_;
  loop::Clock::time_point lastWatchdog_{};
  loop::Clock::time_point lastStatus_{};
  loop::Clock::time_point startTime_{};
  bool warnedStarting_ = false;
  std::uint64_t cyclesAtLastStatus_ = 0;
  std::uint64_t overrunsAtLastStatus_ = 0;
  std::uint64_t lateReadsAtLastStatus_ = 0;
  double cycleRateHz_ = 0.0;
  loop::FaultCode lastLoggedFault_ = loop::FaultCode::None;
  loop::Withheld lastWithheld_ = loop::Withheld::None;
};

}  // namespace volcomp::daemon
