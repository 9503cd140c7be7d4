// Whole processes: the daemon's life cycle under a service manager (daemon.md sections 3 to 5):
// reload on SIGHUP (a broken model is rejected and the running one stays, a new one slews in
// through the limiter, wider limits wait for a restart), stop on SIGTERM while the machine moves
// (ramp-out, zero and status 0 written, exit 0), and the sd_notify protocol against a NOTIFY_SOCKET
// bound by the test, with WATCHDOG_USEC and WATCHDOG_PID set as systemd sets them.

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "notify_listener.hpp"
#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

using testutil::NotifyListener;

class Lifecycle : public ProcessTest {
 protected:
  /// Simulator and daemon, the daemon's model a copy in the temp dir (so that a test can change
  /// it), max_rate 0.05 mm/s = 0.5 um per 10 ms cycle (slews and ramps span several writes).
  Listening startBoth(const std::vector<std::string>& simArgs = {"--port", "0"},
                      const std::vector<std::string>& daemonEnv = {}, bool watchdogPid = false) {
    modelFile_ = writeJson("model.json", example("vmc-xyfz-21.json"));
    json sim = simConfig(exampleFile("vmc-xyfz-21.json"), 500);
    sim["limits"]["max_rate_mm_s"] = kMaxRate;
    sim["heartbeat_timeout_ms"] = 0;
    const Listening at = startSim(sim, simArgs);
    json d = daemonConfig(at, modelFile_);
    d["limiter"]["max_rate_mm_s"] = kMaxRate;
    startDaemon(d, daemonEnv, watchdogPid);
    return at;
  }

  std::vector<std::string> notifyEnv() const { return {"NOTIFY_SOCKET=" + notify_->path()}; }

  void SetUp() override {
    ProcessTest::SetUp();
    notify_ = std::make_unique<NotifyListener>(path("notify.sock"));
  }
  void TearDown() override {
    notify_.reset();
    ProcessTest::TearDown();
  }

  static constexpr double kMaxRate = 0.05;
  static constexpr double kPeriodS = 0.010;
  std::string modelFile_;
  std::unique_ptr<NotifyListener> notify_;
};

// A model file that fails validation: the reload is rejected with a log line saying why and the
// RELOAD_FAILED bit and a "reload failed" STATUS; the running model keeps compensating.
TEST_F(Lifecycle, SighupWithABrokenModelKeepsTheRunningOne) {
  startBoth({"--port", "0"}, notifyEnv());
  ASSERT_TRUE(notify_->waitFor("READY=1", 10s)) << daemonLog();
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  {
    json broken = example("vmc-xyfz-21.json");
    broken["components"]["EXX"]["values"] = "not a table";
    std::ofstream(modelFile_) << broken.dump(2);
  }
  daemon_->signal(SIGHUP);
  ASSERT_TRUE(daemon_->waitForStderr("reload rejected", 10s)) << daemonLog();
  // The log line names the file and the offending key.
  const std::string log = daemonLog();
  const std::string line = log.substr(log.find("reload rejected"));
  EXPECT_NE(line.find("model.json"), std::string::npos) << line;
  EXPECT_NE(line.find("EXX"), std::string::npos) << line;
  // STATUS= (at most once a second) carries the reason too.
  bool statusSaysSo = false;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        const auto m = notify_->receive(100ms);
        statusSaysSo =
            m && m->rfind("STATUS=", 0) == 0 && m->find("reload failed") != std::string::npos;
        return statusSaysSo;
      },
      5s))
      << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 100));
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  // Same model on both sides and still running: the error stays compensated.
  EXPECT_LE(report["rms_compensated_um"].get<double>(),
            0.1 * report["rms_uncompensated_um"].get<double>())
      << report.dump();
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, 0.1, kMaxRate, kPeriodS);
  const std::size_t failed = [&] {
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (rows[i].status & kReloadFailed) return i;
    }
    return rows.size();
  }();
  ASSERT_LT(failed, rows.size());
  for (std::size_t i = failed; i < rows.size(); ++i) {
    EXPECT_TRUE(rows[i].status & kActive) << "t=" << rows[i].tS;
    EXPECT_TRUE(rows[i].status & kReloadFailed) << "t=" << rows[i].tS;
  }
  EXPECT_GT(rows.size() - failed, 40U);
  EXPECT_GT(largestAbs(rows.back().offsetMm), 0.001);
}

// A new model (the same error three times larger) takes effect through the limiter: the
// offsets slew to the new values at max_rate (0.5 um per cycle), no write jumps.
TEST_F(Lifecycle, SighupWithANewModelSlewsToIt) {
  startBoth({"--port", "0"}, notifyEnv());
  ASSERT_TRUE(notify_->waitFor("READY=1", 10s)) << daemonLog();
  ASSERT_TRUE(waitForAppliedOffset(0.004)) << daemonLog();
  std::ofstream(modelFile_) << scaledModel(example("vmc-xyfz-21.json"), 3.0).dump(2);
  daemon_->signal(SIGHUP);
  ASSERT_TRUE(notify_->waitFor("RELOADING=1", 10s)) << daemonLog();
  ASSERT_TRUE(notify_->waitFor("READY=1", 10s)) << daemonLog();
  ASSERT_TRUE(daemon_->waitForStderr("reloaded: model", 5s)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 60));
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, 0.1, kMaxRate, kPeriodS);
  std::size_t reloaded = 0;
  while (reloaded < rows.size() && !(rows[reloaded].status & kModelReloaded)) ++reloaded;
  ASSERT_LT(reloaded, rows.size()) << "no MODEL_RELOADED in the status";
  ASSERT_GT(reloaded, 0U);
  ASSERT_GT(rows.size(), reloaded + 50);
  const double before = largestAbs(rows[reloaded - 1].offsetMm);
  const double after = largestAbs(rows[reloaded + 50].offsetMm);
  EXPECT_GE(before, 0.003);
  // Three times the error, 0.5 s later (the machine moved ~50 mm, the model changed little).
  EXPECT_GT(after, 2.0 * before) << before << " -> " << after;
  // The slew needs (3 - 1) * before / 0.5 um cycles with LIMITED set.
  std::size_t limited = 0;
  for (std::size_t i = reloaded; i < reloaded + 50; ++i) {
    if (rows[i].status & kLimited) ++limited;
  }
  EXPECT_GE(static_cast<double>(limited), 0.9 * (2.0 * before / (kMaxRate * kPeriodS)) - 1.0);
}

// A reload that widens the limiter from 0.1 mm, 0.5 mm/s to 2 mm, 1000 mm/s (both accepted by
// the configuration) together with a model thirty times larger (offsets up to ~0.8 mm): the
// wider limits are not taken while compensating, a warning per limit says old and new values and
// to restart, and the simulator, which checks every write against the old limits, counts no
// violation: the offsets slew at 0.5 mm/s to the 0.1 mm band and stay in it.
TEST_F(Lifecycle, SighupThatWidensTheLimiterKeepsTheRunningLimits) {
  modelFile_ = writeJson("model.json", example("vmc-xyfz-21.json"));
  json sim = simConfig(exampleFile("vmc-xyfz-21.json"), 500);  // limits 0.1 mm, 0.5 mm/s
  sim["heartbeat_timeout_ms"] = 0;
  ASSERT_EQ(sim["limits"]["max_offset_mm"], 0.1);
  ASSERT_EQ(sim["limits"]["max_rate_mm_s"], 0.5);
  const Listening at = startSim(sim, {"--port", "0"});
  json d = daemonConfig(at, modelFile_);  // the same limits
  startDaemon(d, notifyEnv());
  ASSERT_TRUE(notify_->waitFor("READY=1", 10s)) << daemonLog();
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  std::ofstream(modelFile_) << scaledModel(example("vmc-xyfz-21.json"), 30.0).dump(2);
  d["limiter"]["max_offset_mm"] = 2.0;
  d["limiter"]["max_rate_mm_s"] = 1000.0;
  writeJson("volcompd.json", d);
  daemon_->signal(SIGHUP);
  ASSERT_TRUE(daemon_->waitForStderr("reloaded: model", 10s)) << daemonLog();
  // The larger model is taken: the offsets reach the old band, and stay in it.
  ASSERT_TRUE(waitForAppliedOffset(0.1 - kQuantumMm)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50));
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, 0.1, 0.5, kPeriodS);
  const std::string log = daemonLog();
  for (const char* change : {"limiter.max_offset_mm of ", "widens X/Y/Z 0.1 -> 2 mm",
                             "limiter.max_rate_mm_s of ", "widens X/Y/Z 0.5 -> 1000 mm/s",
                             "not taken while compensating", "systemctl restart volcompd"}) {
    EXPECT_NE(log.find(change), std::string::npos) << change << " not in\n" << log;
  }
}

// SIGTERM while the machine moves and the offsets are applied: STOPPING=1, a ramp to zero at
// max_rate with the STOPPING bit, then zero with status 0 ("inactive"), exit 0.
TEST_F(Lifecycle, SigtermWhileMovingRampsOutWritesZeroAndExitsZero) {
  startBoth({"--port", "0"}, notifyEnv());
  ASSERT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  EXPECT_TRUE(notify_->waitFor("STOPPING=1", 2s));
  const json report = finishSim();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  for (double o : report["applied_offset_mm"]) EXPECT_EQ(o, 0.0);
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, 0.1, kMaxRate, kPeriodS);
  std::size_t stop = 0;
  while (stop < rows.size() && !(rows[stop].status & kStopping)) ++stop;
  ASSERT_LT(stop, rows.size());
  ASSERT_GT(stop, 0U);
  EXPECT_GE(largestAbs(rows[stop - 1].offsetMm), 0.005 - kQuantumMm);
  for (std::size_t i = stop; i + 1 < rows.size(); ++i) {
    EXPECT_TRUE(rows[i].status & kStopping) << "t=" << rows[i].tS;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(rows[i].offsetMm[k]), std::abs(rows[i - 1].offsetMm[k]) + 1e-12);
    }
  }
  // 5 um at 0.5 um per cycle: at least 10 writes of ramp before the final zero.
  EXPECT_GE(rows.size() - stop, 10U);
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
  EXPECT_EQ(rows.back().status, 0U) << "status 0 = inactive";
}

// sd_notify as systemd sees it: no READY=1 while the controller refuses the connection (its
// first second), READY=1 after the first good cycle, WATCHDOG=1 from the cycle at least every
// WATCHDOG_USEC/2 (200 ms / 2; the daemon pings at a quarter), STATUS= once a second with the
// state and cycle rate, STOPPING=1 on SIGTERM, exit 0.
TEST_F(Lifecycle, NotifiesReadyWatchdogStatusAndStopping) {
  startBoth({"--port", "0", "--event", "0:drop-link:1"},
            {"NOTIFY_SOCKET=" + notify_->path(), "WATCHDOG_USEC=200000"},
            /*watchdogPid=*/true);
  // READY=1 comes after the first good cycle, so the simulator has counted a write by the time
  // READY=1 is in the socket: a status asked for after READY=1 has been received must show one.
  // (Asking first and draining after would race: READY=1 may arrive between the two.)
  bool ready = false;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        while (auto m = notify_->receive(0ms)) {
          if (NotifyListener::hasLine(*m, "READY=1")) ready = true;
        }
        return ready;
      },
      10s))
      << daemonLog();
  {
    const json s = simStatus();
    ASSERT_TRUE(s.is_object());
    EXPECT_GT(s["writes"].get<int>(), 0) << "READY=1 before the first write reached the controller";
  }
  const auto firstStatus = notify_->waitFor("WATCHDOG=1", 2s);
  ASSERT_TRUE(firstStatus) << "no WATCHDOG=1 with WATCHDOG_PID set to the daemon's pid";
  // Count pings over two STATUS periods (2 s): at 200 ms / 4 = 50 ms there are ~40.
  std::size_t statuses = 0, pings = 0;
  std::string status;
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        const auto m = notify_->receive(100ms);
        if (!m) return false;
        if (NotifyListener::hasLine(*m, "WATCHDOG=1")) ++pings;
        if (m->rfind("STATUS=", 0) == 0) {
          status = *m;
          ++statuses;
        }
        return statuses == 2;
      },
      5s));
  EXPECT_GE(pings, 20U);
  EXPECT_EQ(status.rfind("STATUS=active", 0), 0U) << status;
  EXPECT_NE(status.find(" Hz"), std::string::npos) << status;
  daemon_->signal(SIGTERM);
  EXPECT_TRUE(notify_->waitFor("STOPPING=1", 5s)) << daemonLog();
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  const json report = finishSim();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty());
  EXPECT_GE(rows.front().tS, 1.0) << "no write while the link was refused";
}

}  // namespace
}  // namespace volcomp::e2e
