// Whole processes under hostile conditions: a read-back of the applied offsets
// outside +-max_offset (left over by an earlier run, or a garbled reply) is a fault of its own and
// is never taken over, never written past the band, and does not hold a stop; a reload blocked on
// file I/O (a FIFO as the model) does not hold a stop either.

#include <sys/stat.h>

#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

class HostileConditions : public ProcessTest {
 protected:
  static std::size_t occurrences(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
    return n;
  }
  json simWith(double heartbeatTimeoutMs) const {
    json s = simConfig(exampleFile("vmc-xyfz-21.json"), 0);
    s["limits"]["max_offset_mm"] = kMaxOffsetMm;
    s["limits"]["max_rate_mm_s"] = kMaxRateMmS;
    s["heartbeat_timeout_ms"] = heartbeatTimeoutMs;
    s["watchdog_ramp_mm_s"] = 0.5;
    return s;
  }
  json daemonFor(const Listening& at) const {
    json d = daemonConfig(at, exampleFile("vmc-xyfz-21.json"));
    d["limiter"]["max_offset_mm"] = kMaxOffsetMm;
    d["accept_model_beyond_max_offset"] = true;  // the model exceeds max_offset on purpose
    d["limiter"]["max_rate_mm_s"] = kMaxRateMmS;
    return d;
  }
  /// Nothing past the band, no step beyond the limiter, in the record and by the simulator.
  /// `watchdogGapS`: a silence after which the controller's watchdog may have ramped the offsets
  /// (the step across it is the simulator's to judge, against what it applied then).
  void expectRecordWithinLimits(
      const json& report, double watchdogGapS = std::numeric_limits<double>::infinity()) const {
    EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
    expectWritesWithinLimits(record(), kMaxOffsetMm, kMaxRateMmS, 0.010, watchdogGapS);
  }

  static constexpr double kMaxOffsetMm = 0.1;
  static constexpr double kMaxRateMmS = 0.5;
};

// The controller holds 0.15 mm on X from an earlier run with other limits; this daemon allows
// 0.1 mm. It logs the fault, writes nothing while the read-back is outside the band (its
// heartbeat stays silent, so the controller's watchdog removes the offsets at its own rate), and
// continues from the read-back once it is inside: its first write is within the band and one
// step from what is applied.
TEST_F(HostileConditions, LeftOverOffsetOutsideTheBandIsNeverTakenOver) {
  json s = simWith(300.0);
  s["initial_offset_mm"] = {0.15, 0.01, 0.0};
  const Listening at = startSim(s, {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(daemon_->waitForStderr("readback-out-of-range", 15s)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50, 20s)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  expectRecordWithinLimits(report);
  const auto rows = record();
  ASSERT_FALSE(rows.empty());
  EXPECT_LE(std::abs(rows.front().offsetMm[0]), kMaxOffsetMm + kQuantumMm);
  EXPECT_GE(report["watchdog_trips"].get<int>(), 1);
  // The log names the value read back: 0.15 mm, or less when the controller's watchdog had
  // already ramped part of it out before the daemon's first read (a slow start).
  const std::string log = daemonLog();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(log, m, std::regex("applied offsets read back \\+([0-9.]+) ")))
      << log;
  const double readBackMm = std::stod(m[1].str());
  EXPECT_GT(readBackMm, kMaxOffsetMm) << log;
  EXPECT_LE(readBackMm, 0.15) << log;
  // Once each: the values that caused the fault and the return into the band.
  EXPECT_EQ(occurrences(log, ", outside +-max_offset_mm"), 1U) << log;
  EXPECT_EQ(occurrences(log, "inside +-max_offset_mm again"), 1U) << log;
}

// While active, the X read-back reports 150 mm for 0.6 s (a garbled reply): fault, nothing
// written meanwhile (the writes stop), no write past the band ever; afterwards the loop continues
// from the read-back. With the latch the fault stays until acknowledged (here: enable toggled).
TEST_F(HostileConditions, GarbledReadBackWhileActiveWritesNothingAndNeverPastTheBand) {
  const Listening at = startSim(simWith(300.0), {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  sim_->writeLine("garble-readback 150 0.6");
  ASSERT_TRUE(daemon_->waitForStderr("fault: readback-out-of-range", 10s)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 30, 20s)) << daemonLog();  // after the garble
  sim_->writeLine("enable off");
  ASSERT_TRUE(waitForMoreWrites(*sim_, 5)) << daemonLog();
  sim_->writeLine("enable on");
  ASSERT_TRUE(waitForMoreWrites(*sim_, 30)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  // Across the 0.6 s without writes the controller's watchdog (300 ms) ramped the offsets out:
  // the first write after it is judged against that by the simulator, not against the last
  // write before it (which may be more than one step from zero: a cycle that ran past its
  // deadline is followed at once by the next, so two steps may precede the garble).
  expectRecordWithinLimits(report, 0.3);
  const auto rows = record();
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.4) gap = i;
  }
  EXPECT_GT(gap, 0U) << "no writes while the read-back was garbled";
  const std::string log = daemonLog();
  EXPECT_NE(log.find("latched fault acknowledged"), std::string::npos) << log;
  EXPECT_TRUE(rows.back().status & kActive);
  // The garbled values once, the return into the band once; no fault line repeats values.
  EXPECT_EQ(occurrences(log, "applied offsets read back +150.0000"), 1U) << log;
  EXPECT_EQ(occurrences(log, ", outside +-max_offset_mm"), 1U) << log;
  EXPECT_EQ(occurrences(log, "inside +-max_offset_mm again"), 1U) << log;
}

// SIGTERM while the read-back stays garbled: nothing can be written, and the stop ends at its
// bounded deadline (here 2 x ramp + 1 s of the daemon's own offsets), not after a 300 s ramp from
// 150 mm; exit 0.
TEST_F(HostileConditions, StopWithAGarbledReadBackEndsInBoundedTime) {
  const Listening at = startSim(simWith(0.0), {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  sim_->writeLine("garble-readback 150");
  ASSERT_TRUE(daemon_->waitForStderr("readback-out-of-range", 10s)) << daemonLog();
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(12s), 0) << daemonLog();
  const json report = finishSim();
  expectRecordWithinLimits(report);
}

// The configuration's model becomes a FIFO nobody writes to (a model on a hung mount): SIGHUP
// starts a reload that blocks in open(). SIGTERM must still ramp out, write zero with status 0
// and exit 0, whatever the reload is doing.
TEST_F(HostileConditions, StopRampsOutAndExitsWhileAReloadBlocksOnAFifo) {
  const Listening at = startSim(simWith(0.0), {"--port", "0"});
  json d = daemonFor(at);
  startDaemon(d);
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  const std::string fifo = path("model.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  d["model"] = fifo;
  writeJson("volcompd.json", d);
  daemon_->signal(SIGHUP);
  ASSERT_TRUE(daemon_->waitForStderr("reloading configuration and model", 10s)) << daemonLog();
  daemon_->signal(SIGHUP);  // remembered behind the blocked one, not a second thread
  ASSERT_TRUE(daemon_->waitForStderr("it follows that one", 10s)) << daemonLog();
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  ASSERT_TRUE(waitForSim(
      [](const json& s) {
        return largestAbs(s["applied_offset_mm"].get<std::array<double, 3>>()) == 0.0;
      },
      5s));
  const json report = finishSim();
  expectRecordWithinLimits(report);
  const auto rows = record();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back().status, 0U);
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
}

}  // namespace
}  // namespace volcomp::e2e
