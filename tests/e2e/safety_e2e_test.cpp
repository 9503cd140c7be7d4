// Whole processes: the safety rules of daemon.md sections 2 and 3 seen on the wire, i.e. in the
// simulator's record of every write: the limiter, enable and homed, link loss (dropped link and a
// controller restarted on the same port), transaction timeouts, exception replies and frozen
// inputs. Faults are injected with the simulator's --event T:COMMAND[:ARG] (T in the simulator's
// seconds, the same clock as the record's t_s) or its stdin commands.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

class Safety : public ProcessTest {
 protected:
  /// Simulator and daemon with the same model and the same limits (the simulator checks every
  /// write against its own copy of them).
  void configure(double maxOffsetMm, double maxRateMmS, const std::string& model) {
    model_ = model;
    maxOffsetMm_ = maxOffsetMm;
    maxRateMmS_ = maxRateMmS;
    sim_cfg_ = simConfig(model, 0);
    sim_cfg_["limits"]["max_offset_mm"] = maxOffsetMm;
    sim_cfg_["limits"]["max_rate_mm_s"] = maxRateMmS;
    // The controller keeps the applied offsets while the daemon is away (no PLC watchdog), so
    // that a jump on reconnection would show in the record.
    sim_cfg_["heartbeat_timeout_ms"] = 0;
  }

  json daemonFor(const Listening& at) const {
    json d = daemonConfig(at, model_);
    d["limiter"]["max_offset_mm"] = maxOffsetMm_;
    d["limiter"]["max_rate_mm_s"] = maxRateMmS_;
    // These tests drive the limiter with models that ask for more than max_offset on purpose;
    // without this the daemon refuses such a model before it starts.
    d["accept_model_beyond_max_offset"] = true;
    return d;
  }

  void expectWithinLimits(const std::vector<WriteRow>& rows) const {
    expectWritesWithinLimits(rows, maxOffsetMm_, maxRateMmS_, kPeriodS);
  }

  static constexpr double kPeriodS = 0.010;  // cycle_period_ms of volcompd-modbus-tcp.json
  std::string model_;
  double maxOffsetMm_ = 0.1;
  double maxRateMmS_ = 0.5;
  json sim_cfg_;
};

/// Index of the first row at or after `fromS` whose status has `bit`, or rows.size().
std::size_t firstWith(const std::vector<WriteRow>& rows, unsigned bit, double fromS = 0.0) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].tS >= fromS && (rows[i].status & bit) != 0) return i;
  }
  return rows.size();
}

/// From row `from` on, every axis moves monotonically towards zero, reaches exactly zero and
/// stays there; returns the index of the first all-zero row.
std::size_t expectRampToZero(const std::vector<WriteRow>& rows, std::size_t from) {
  std::size_t zeroAt = rows.size();
  for (std::size_t i = from + 1; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(rows[i].offsetMm[k]), std::abs(rows[i - 1].offsetMm[k]) + 1e-12)
          << "axis " << k << " moved away from zero at t=" << rows[i].tS;
      if (rows[i - 1].offsetMm[k] != 0.0) {
        EXPECT_GE(rows[i].offsetMm[k] * rows[i - 1].offsetMm[k], 0.0) << "crossed zero";
      }
    }
    if (zeroAt == rows.size() && largestAbs(rows[i].offsetMm) == 0.0) zeroAt = i;
  }
  return zeroAt;
}

// The limiter: the model (the example scaled x8, up to ~115 um on this path) asks for more than
// max_offset (20 um) and, from the zero start, for steps larger than max_rate * dt (0.1 mm/s *
// 10 ms = 1 um). Every write must respect both, the LIMITED bit must be set, and the clamp must
// be reached.
TEST_F(Safety, LimiterBoundsEveryWriteAndSetsTheLimitedBit) {
  const std::string model =
      writeJson("model-x8.json", scaledModel(example("vmc-xyfz-21.json"), 8.0));
  configure(0.020, 0.1, model);
  const Listening at = startSim(sim_cfg_, {"--port", "0", "--duration", "2.5"});
  startDaemon(daemonFor(at));
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["offset_violations"], 0);
  EXPECT_EQ(report["rate_violations"], 0);
  EXPECT_GT(report["max_uncompensated_um"].get<double>(), 40.0) << "the model must ask for more";

  const auto rows = record();
  ASSERT_GT(rows.size(), 100U);
  expectWithinLimits(rows);
  std::size_t limited = 0, clamped = 0;
  for (const auto& r : rows) {
    if (r.status & kLimited) ++limited;
    if (largestAbs(r.offsetMm) >= 0.020 - kQuantumMm) {
      ++clamped;
      EXPECT_TRUE(r.status & kLimited) << "clamped write without LIMITED at t=" << r.tS;
    }
    EXPECT_TRUE(r.status & kActive) << "t=" << r.tS;
  }
  EXPECT_GT(limited, 20U);
  EXPECT_GT(clamped, 20U);
  // The ramp-in from zero is rate-limited: reaching 20 um at 1 um per cycle takes >= 19 writes.
  std::size_t firstClamped = 0;
  while (firstClamped < rows.size() && largestAbs(rows[firstClamped].offsetMm) < 0.0199) {
    ++firstClamped;
  }
  EXPECT_GE(firstClamped, 19U);
}

// Enable off: the offsets ramp to zero at max_rate (0.05 mm/s = 0.5 um per cycle, so a 5 um
// offset takes >= 10 writes), then zero is written; DISABLED replaces ACTIVE in the status.
TEST_F(Safety, EnableOffRampsToZeroAndStaysThere) {
  configure(0.1, 0.05, exampleFile("vmc-xyfz-21.json"));
  const Listening at = startSim(sim_cfg_, {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  sim_->writeLine("enable off");
  std::uint64_t writesAtZero = 0;
  ASSERT_TRUE(waitForSim(
      [&](const json& s) {
        if (largestAbs(s["applied_offset_mm"].get<std::array<double, 3>>()) != 0.0) return false;
        if (writesAtZero == 0) writesAtZero = s["writes"].get<std::uint64_t>();
        return s["writes"].get<std::uint64_t>() > writesAtZero + 20;
      },
      10s))
      << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];

  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);
  const std::size_t off = firstWith(rows, kDisabled);
  ASSERT_LT(off, rows.size());
  ASSERT_GT(off, 0U);
  EXPECT_GE(largestAbs(rows[off - 1].offsetMm), 0.005 - kQuantumMm);
  for (std::size_t i = 0; i < off; ++i) EXPECT_TRUE(rows[i].status & kActive);
  for (std::size_t i = off; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].status & (kActive | kDisabled), kDisabled) << "t=" << rows[i].tS;
  }
  const std::size_t zeroAt = expectRampToZero(rows, off - 1);
  ASSERT_LT(zeroAt, rows.size());
  EXPECT_GE(zeroAt - (off - 1), 10U) << "a ramp at 0.5 um per cycle, not a jump";
  EXPECT_GE(rows.size() - zeroAt, 20U) << "zero keeps being written";
}

// Not homed: nothing but zero is written (status DISABLED), until the axes are homed; then the
// offsets ramp in from zero.
TEST_F(Safety, NotHomedWritesOnlyZeroUntilHomed) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  const Listening at = startSim(sim_cfg_, {"--port", "0", "--duration", "2.5", "--event",
                                           "0:homed:off", "--event", "1.2:homed:on"});
  startDaemon(daemonFor(at));
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);
  std::size_t before = 0, after = 0;
  for (const auto& r : rows) {
    if (r.tS < 1.2) {
      ++before;
      EXPECT_EQ(largestAbs(r.offsetMm), 0.0) << "t=" << r.tS;
      EXPECT_EQ(r.status & (kActive | kDisabled), kDisabled) << "t=" << r.tS;
    } else if (r.tS > 1.4) {
      ++after;
      EXPECT_TRUE(r.status & kActive) << "t=" << r.tS;
    }
  }
  EXPECT_GT(before, 50U) << daemonLog();
  ASSERT_GT(after, 50U);
  EXPECT_GT(largestAbs(rows.back().offsetMm), 0.001);
}

// A dropped link (the controller closes the connection and refuses new ones for 0.8 s): the
// daemon reconnects, reads the applied offsets back and continues from them: the first write
// after the outage is within one limiter step of the last one before it.
TEST_F(Safety, DroppedLinkReconnectsAndContinuesWithoutAJump) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  const Listening at =
      startSim(sim_cfg_, {"--port", "0", "--duration", "4", "--event", "1.5:drop-link:0.8"});
  startDaemon(daemonFor(at));
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_EQ(report["sessions"], 2) << daemonLog();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);  // includes the step across the gap
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.5) gap = i;
  }
  ASSERT_GT(gap, 0U) << "no outage in the record";
  EXPECT_GE(rows[gap].tS, 2.3);
  EXPECT_GT(largestAbs(rows[gap - 1].offsetMm), 0.001) << "offsets were applied before";
  EXPECT_GT(rows.back().tS, 3.5);
  EXPECT_NE(daemonLog().find("link lost"), std::string::npos) << daemonLog();
}

// RTU: a silent controller (drop-link on a serial line: no answers for 0.8 s) costs timeouts,
// the daemon declares the link lost, reopens the device and continues without a jump.
TEST_F(Safety, RtuSilenceReconnectsAndContinuesWithoutAJump) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  const Listening at =
      startSim(sim_cfg_, {"--rtu", "--duration", "4", "--event", "1.5:drop-link:0.8"});
  ASSERT_EQ(at.kind, "rtu");
  json d = daemonConfig(at, model_, "volcompd-modbus-rtu.json");
  const double periodS = d["cycle_period_ms"].get<double>() / 1000.0;
  startDaemon(d);
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_GT(report["requests_unanswered"].get<int>(), 0);
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, 0.1, 0.5, periodS);
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.5) gap = i;
  }
  ASSERT_GT(gap, 0U) << "no outage in the record";
  EXPECT_GE(rows[gap].tS, 2.3);
  EXPECT_GT(rows.back().tS, 3.5) << daemonLog();
  EXPECT_TRUE(rows.back().status & kActive);
  EXPECT_NE(daemonLog().find("link lost"), std::string::npos) << daemonLog();
}

// The controller process dies (SIGTERM: it records its writes and exits) and a new one starts
// on the same port holding the offsets the old one applied (as a real controller keeps them):
// the daemon reconnects on its own and its first write steps from those by at most max_rate*dt.
TEST_F(Safety, RestartedControllerOnTheSamePortGetsNoJump) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  Listening at = startSim(sim_cfg_, {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.004)) << daemonLog();
  sim_->signal(SIGTERM);
  const json first = finishSim(/*sendQuit=*/false);
  ASSERT_TRUE(first.is_object());
  ASSERT_TRUE(daemon_->waitForStderr("link lost", 10s)) << daemonLog();

  json second = sim_cfg_;
  second["initial_offset_mm"] = first["applied_offset_mm"];
  Listening again;
  auto sim2 = spawnSim(second, {"--port", std::to_string(at.port)}, "sim2", again);
  ASSERT_EQ(again.port, at.port);
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        const json s = statusOf(*sim2);
        return s.is_object() && s["writes"].get<int>() >= 50;
      },
      15s))
      << daemonLog();
  const json report = finish(*sim2);
  stopDaemon();
  EXPECT_EQ(first["limiter_violations"], 0) << first["first_violation"];
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["sessions"], 1);

  auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  const auto rows2 = record("sim2");
  ASSERT_FALSE(rows.empty());
  ASSERT_FALSE(rows2.empty());
  // The old controller's last write is what it applied; the new one's first write steps from
  // there by one limiter step at most.
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_NEAR(rows.back().offsetMm[k], first["applied_offset_mm"][k].get<double>(), 1e-9);
  }
  rows.insert(rows.end(), rows2.begin(), rows2.end());
  expectWithinLimits(rows);
  EXPECT_TRUE(rows.back().status & kActive);
}

// The daemon hangs (SIGSTOP: a starved or stuck process) with the link up; the controller's
// heartbeat watchdog (300 ms) removes the offsets itself, as daemon.md section 3 asks of the PLC.
// When the daemon runs again (SIGCONT) the controller applies zero, so its first write may step
// from zero by one limiter step at most (0.05 mm/s * 10 ms = 0.5 um, plus one count); writing
// the offsets it held before the hang (>= 4 um) would be a jump at the machine.
TEST_F(Safety, ResumedDaemonContinuesFromWhatTheControllerApplies) {
  configure(0.1, 0.05, exampleFile("vmc-xyfz-21.json"));
  sim_cfg_["heartbeat_timeout_ms"] = 300;
  sim_cfg_["watchdog_ramp_mm_s"] = 0.5;
  const Listening at = startSim(sim_cfg_, {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.004)) << daemonLog();
  daemon_->signal(SIGSTOP);
  std::size_t writesBefore = 0;
  ASSERT_TRUE(waitForSim(
      [&](const json& s) {
        writesBefore = s["writes"].get<std::size_t>();
        return s["watchdog_trips"].get<int>() >= 1 &&
               largestAbs(s["applied_offset_mm"].get<std::array<double, 3>>()) == 0.0;
      },
      10s));
  daemon_->signal(SIGCONT);
  ASSERT_TRUE(waitForMoreWrites(*sim_, 30)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  const auto rows = record();
  ASSERT_GT(rows.size(), writesBefore) << daemonLog();
  EXPECT_GE(largestAbs(rows[writesBefore - 1].offsetMm), 0.004 - kQuantumMm);
  EXPECT_LE(largestAbs(rows[writesBefore].offsetMm), 0.05 * kPeriodS + kQuantumMm + 1e-9)
      << "first write after the hang at t=" << rows[writesBefore].tS << ": "
      << rows[writesBefore].offsetMm[0] << ", " << rows[writesBefore].offsetMm[1] << ", "
      << rows[writesBefore].offsetMm[2] << " mm while the controller applied zero";
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
}

// Stall (the controller receives requests and never answers) for 0.6 s: transactions time out
// (50 ms each), the daemon declares the link lost after 3, reconnects when the controller
// answers again and continues from the read-back. Nothing can be written while the controller
// is silent, so the ramp-out of that fault cannot appear on the wire; what must hold there is
// that the first write after it is within one step of the last before it.
TEST_F(Safety, StallTimesOutAndRecoversWithoutAJump) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  const Listening at =
      startSim(sim_cfg_, {"--port", "0", "--duration", "3.5", "--event", "1:stall:0.6"});
  startDaemon(daemonFor(at));
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_GT(report["requests_unanswered"].get<int>(), 0);
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const std::string log = daemonLog();
  EXPECT_TRUE(log.find("fault: transaction-error") != std::string::npos ||
              log.find("link lost") != std::string::npos)
      << log;
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.3) gap = i;
  }
  ASSERT_GT(gap, 0U) << "no gap in the writes during the stall";
  EXPECT_GE(rows[gap].tS, 1.6);
  EXPECT_GT(rows.back().tS, 3.0) << log;
  EXPECT_TRUE(rows.back().status & kActive);
  EXPECT_GT(largestAbs(rows.back().offsetMm), 0.001);
}

// Exception replies (code 4, server device failure) to every request for 0.5 s: a transaction
// error fault, then recovery to active once the controller answers, without a jump.
TEST_F(Safety, ExceptionRepliesFaultAndRecover) {
  configure(0.1, 0.5, exampleFile("vmc-xyfz-21.json"));
  const Listening at =
      startSim(sim_cfg_, {"--port", "0", "--duration", "3", "--event", "1:exception:4:0.5"});
  startDaemon(daemonFor(at));
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_GT(report["exceptions_sent"].get<int>(), 0);
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const std::string log = daemonLog();
  const auto fault = log.find("-> fault: transaction-error");
  ASSERT_NE(fault, std::string::npos) << log;
  EXPECT_NE(log.find("fault -> active", fault), std::string::npos) << log;
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);
  ASSERT_FALSE(rows.empty());
  EXPECT_GT(rows.back().tS, 2.5);
  EXPECT_TRUE(rows.back().status & kActive);
}

// Frozen inputs: the input registers keep their last values while the machine moves on (a PLC
// that stopped updating them). With a life counter mapped, its standstill is the sign; without
// one, `frozen_positions_are_stale` makes the standstill of moving positions the sign. Either
// way: fault "stale input" (code 1) once the stale timeout (500 ms) has passed, the offsets ramp
// to zero (0.5 um per cycle), and compensation resumes when the registers move again.
class FrozenInputs : public Safety, public ::testing::WithParamInterface<bool> {};

TEST_P(FrozenInputs, FaultAfterTheStaleTimeoutRampOutAndRecovery) {
  const bool lifeCounter = GetParam();
  configure(0.1, 0.05, exampleFile("vmc-xyfz-21.json"));
  if (!lifeCounter) sim_cfg_["transport"]["registers"].erase("sequence");
  const Listening at =
      startSim(sim_cfg_, {"--port", "0", "--duration", "3.4", "--event", "1:freeze:1.2"});
  json d = daemonFor(at);
  d["fault_latch"] = false;  // the fault clears with its cause (the latch: latch_saturation_e2e)
  if (!lifeCounter) {
    d["transport"]["registers"].erase("sequence");
    d["frozen_positions_are_stale"] = true;
  }
  startDaemon(d);
  const json report = finishSim(/*sendQuit=*/false);
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWithinLimits(rows);
  const std::size_t fault = firstWith(rows, kFault);
  ASSERT_LT(fault, rows.size()) << daemonLog();
  ASSERT_GT(fault, 0U);
  // Frozen at 1.0 s; the last fresh read was at most one cycle before that, so the fault is
  // declared 0.5 s (stale timeout) after it, within a few cycles.
  EXPECT_GE(rows[fault].tS, 1.0 + 0.5 - 0.02);
  EXPECT_LE(rows[fault].tS, 1.0 + 0.5 + 0.1);
  EXPECT_EQ(faultCodeOf(rows[fault].status), 1U) << "stale-input";
  EXPECT_GE(largestAbs(rows[fault - 1].offsetMm), 0.002);
  // Ramp-out during the fault, reaching zero before the registers move again at 2.2 s.
  std::size_t end = fault;
  while (end < rows.size() && (rows[end].status & kFault)) ++end;
  const std::vector<WriteRow> faulted(rows.begin() + static_cast<std::ptrdiff_t>(fault - 1),
                                      rows.begin() + static_cast<std::ptrdiff_t>(end));
  const std::size_t zeroAt = expectRampToZero(faulted, 0);
  ASSERT_LT(zeroAt, faulted.size()) << "did not reach zero during the fault";
  EXPECT_GE(zeroAt, 4U) << "a ramp, not a jump";
  // Recovery: active again after the freeze, offsets slewing back in.
  ASSERT_LT(end, rows.size());
  EXPECT_GE(rows[end].tS, 2.2 - 0.02);
  EXPECT_TRUE(rows.back().status & kActive);
  EXPECT_GT(largestAbs(rows.back().offsetMm), 0.001);
}

INSTANTIATE_TEST_SUITE_P(Registers, FrozenInputs, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& param) {
                           return param.param ? std::string("LifeCounter")
                                              : std::string("PositionsOnly");
                         });

}  // namespace
}  // namespace volcomp::e2e
