// Whole processes: the timing faults that used to give one-write jumps at the
// controller, each over Modbus TCP and RTU, each checked on the simulator's record of every write
// against what the controller applied at that moment (its rate check measures the controller's
// own time between the writes it applies).
// - a write applied but answered after the client's timeout, or never answered;
// - the daemon stopped (SIGSTOP) between the read of a cycle and its write while the
//   controller's heartbeat watchdog removes the offsets (the simulator stops it before it
//   answers the read, so that the pause falls between read and write every time);
// - a short pause (a late cycle) followed by an on-time cycle: steps per measured time.
// The faults hit while the offsets ramp in at the rate limit (a model asking for more than the
// band, a slow max_rate), where a wrong rule shows as a step of two limiter steps.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

struct Link {
  bool rtu = false;
  std::string name() const { return rtu ? "Rtu" : "Tcp"; }
};

class TimingFaults : public ProcessTest, public ::testing::WithParamInterface<Link> {
 protected:
  /// The simulator with the example model scaled x8 (so that the offsets ramp towards the band
  /// for ~2 s at 0.05 mm/s), the given PLC heartbeat watchdog, serving TCP or RTU.
  Listening startRamping(const std::vector<std::string>& args, double heartbeatTimeoutMs = 0) {
    model_ = writeJson("model-x8.json", scaledModel(example("vmc-xyfz-21.json"), 8.0));
    json s = simConfig(model_, 0);
    s["limits"]["max_offset_mm"] = kMaxOffsetMm;
    s["limits"]["max_rate_mm_s"] = kMaxRateMmS;
    s["limits"]["cycle_ms"] = periodMs();
    s["heartbeat_timeout_ms"] = heartbeatTimeoutMs;
    s["watchdog_ramp_mm_s"] = kMaxRateMmS;
    std::vector<std::string> a = args;
    if (GetParam().rtu) {
      a.push_back("--rtu");
    } else {
      a.insert(a.end(), {"--port", "0"});
    }
    const Listening at = startSim(s, a);
    EXPECT_EQ(at.kind, GetParam().rtu ? "rtu" : "tcp");
    return at;
  }

  json daemonFor(const Listening& at) const {
    json d = daemonConfig(at, model_,
                          GetParam().rtu ? "volcompd-modbus-rtu.json" : "volcompd-modbus-tcp.json");
    d["limiter"]["max_offset_mm"] = kMaxOffsetMm;
    d["accept_model_beyond_max_offset"] = true;  // the model exceeds max_offset on purpose
    d["limiter"]["max_rate_mm_s"] = kMaxRateMmS;
    d["limiter"]["saturation_fault_ms"] = 0;  // the x8 model clamps: not the point here
    return d;
  }

  double periodMs() const { return GetParam().rtu ? 20.0 : 10.0; }

  /// The record, checked by the test itself: within the band, and never faster than max_rate
  /// between consecutive writes (one step of one period at most, plus a register count).
  std::vector<WriteRow> checkedRecord() const {
    const auto rows = record();
    EXPECT_GT(rows.size(), 50U) << daemonLog();
    expectWritesWithinLimits(rows, kMaxOffsetMm, kMaxRateMmS, periodMs() / 1000.0);
    return rows;
  }

  static constexpr double kMaxOffsetMm = 0.1;
  static constexpr double kMaxRateMmS = 0.05;
  std::string model_;
};

/// The late reads volcompd reports when it stops ("stopped after N cycles (M overruns); K late
/// reads, ..."), or -1.
int lateReadsLogged(const std::string& log) {
  const auto stopped = log.rfind("stopped after");
  if (stopped == std::string::npos) return -1;
  const auto late = log.find(" late reads", stopped);
  if (late == std::string::npos) return -1;
  const auto start = log.rfind(' ', late - 1);
  return std::stoi(log.substr(start + 1, late - start - 1));
}

std::string linkName(const ::testing::TestParamInfo<Link>& info) {
  return info.param.name();
}

// Writes applied by the controller but answered after the daemon's 50 ms response timeout, and
// writes applied and never answered, once the offsets ramp in (2 um applied): the daemon cannot
// know whether they were applied; whatever it writes next is within one step of both possibilities,
// so the record (which applied them) shows no step beyond the limiter. Each fault is given once the
// previous one has been served (not at fixed times: a slow start, on a loaded machine or in a
// sanitizer build, would otherwise let a later event overwrite an earlier one's count).
TEST_P(TimingFaults, WritesAppliedButAnsweredLateOrNeverGetNoJump) {
  const Listening at = startRamping({});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.002)) << daemonLog();
  const auto serve = [&](const std::string& command, const char* counter, int atLeast) {
    sim_->writeLine(command);
    return waitForSim([&](const json& s) { return s[counter].get<int>() >= atLeast; }, 20s);
  };
  ASSERT_TRUE(serve("late-reply 0.08 3", "late_replies", 3)) << daemonLog();
  ASSERT_TRUE(serve("no-reply 3", "replies_dropped", 3)) << daemonLog();
  ASSERT_TRUE(serve("late-reply 0.12 1", "late_replies", 4)) << daemonLog();
  ASSERT_TRUE(waitForSim([](const json& s) { return s["writes"].get<int>() >= 200; }, 30s))
      << simStatus().dump() << "\n"
      << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  checkedRecord();
  EXPECT_NE(daemonLog().find("fault: transaction-error"), std::string::npos) << daemonLog();
}

// The daemon is stopped for 0.8 s after the controller sampled the inputs of a read and before
// the daemon writes; the controller's heartbeat watchdog (200 ms) ramps the offsets out
// meanwhile. The daemon then finds its read older than read_to_write_max_ms, reads again and
// continues from what is applied: the first write after the pause is one step from it.
TEST_P(TimingFaults, DaemonStoppedBetweenReadAndWriteNeverWritesFromTheOldReadBack) {
  const Listening at = startRamping({}, 200.0);
  json d = daemonFor(at);
  d["plc_heartbeat_timeout_ms"] = 200;  // read_to_write_max_ms: 100
  startDaemon(d);
  ASSERT_TRUE(waitForAppliedOffset(0.02)) << daemonLog();
  sim_->writeLine("pause-client " + std::to_string(daemon_->pid()) + " 0.8");
  ASSERT_TRUE(waitForSim(
      [](const json& s) {
        return s["client_pauses"].get<int>() == 1 && s["watchdog_trips"].get<int>() >= 1;
      },
      15s))
      << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  // The simulator checked every write against what it applied at that moment, the first one
  // after the pause against the offsets its watchdog had ramped out meanwhile.
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  // The pause is in the record as a gap; the controller ramped out during it (watchdog at
  // 0.05 mm/s for 0.6 s: 30 um), and the first write after it is near what it applied then.
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.5) gap = i;
  }
  ASSERT_GT(gap, 0U) << "no pause in the record";
  // Consecutive writes on either side of the gap, checked by the test itself (across it the
  // controller, not the daemon, moved the offsets).
  const std::vector<WriteRow> before(rows.begin(), rows.begin() + static_cast<long>(gap));
  const std::vector<WriteRow> after(rows.begin() + static_cast<long>(gap), rows.end());
  expectWritesWithinLimits(before, kMaxOffsetMm, kMaxRateMmS, periodMs() / 1000.0);
  expectWritesWithinLimits(after, kMaxOffsetMm, kMaxRateMmS, periodMs() / 1000.0);
  for (const WriteRow& row : rows) EXPECT_FALSE(row.violation) << "t=" << row.tS;
  // At least the 20 um waited for above (the pause often catches the very write that reached it).
  EXPECT_GE(largestAbs(rows[gap - 1].offsetMm), 0.02 - 1e-9);
  EXPECT_LT(largestAbs(rows[gap].offsetMm), largestAbs(rows[gap - 1].offsetMm) - 0.01)
      << "the first write after the pause continues from the ramped-out offsets";
  EXPECT_GE(lateReadsLogged(daemonLog()), 1) << daemonLog();
}

// Short pauses (one cycle late by 80 % of a period, then on time again), repeated while the
// offsets ramp: each step is limited by max_rate times the time since the previous write, so
// the controller never sees two steps within one period.
TEST_P(TimingFaults, LateCyclesDoNotBunchSteps) {
  const Listening at = startRamping({});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.002)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 60)) << daemonLog();
  const double pauseS = 0.8 * periodMs() / 1000.0;
  for (int i = 0; i < 10; ++i) {
    sim_->writeLine("pause-client " + std::to_string(daemon_->pid()) + " " +
                    std::to_string(pauseS));
    ASSERT_TRUE(
        waitForSim([&](const json& s) { return s["client_pauses"].get<int>() == i + 1; }, 10s))
        << daemonLog();
  }
  ASSERT_TRUE(waitForMoreWrites(*sim_, 20)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = checkedRecord();
  // Late cycles did happen: pairs of writes closer than half a period.
  std::size_t close = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS < 0.5 * periodMs() / 1000.0) ++close;
  }
  EXPECT_GT(close, 0U);
}

INSTANTIATE_TEST_SUITE_P(Links, TimingFaults, ::testing::Values(Link{false}, Link{true}), linkName);

}  // namespace
}  // namespace volcomp::e2e
