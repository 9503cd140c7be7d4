// Whole processes over real SocketCAN: volcomp-sim serving the example CAN configuration
// (config/examples/sim-vmc-can.json) on the test's vcan interface, and volcompd with the matching
// daemon configuration (volcompd-can.json), both started as processes, synchronised on the
// simulator's stdout (LISTENING line, STATUS replies, final report) and on process exit. The
// simulator's true error model is the daemon's model, so compensation must remove nearly all of
// the error; every write is checked against the limiter. Run by run_vcan_tests.sh, which copies
// both executables (and the examples) into the QEMU guest at the same paths.
#include <signal.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "process_fixture.hpp"
#include "vcan_util.hpp"

namespace volcomp::e2e {
namespace {

// The example limiter (volcompd-can.json and sim-vmc-can.json): 0.1 mm, 0.5 mm/s, 10 ms cycle.
constexpr double kMaxOffsetMm = 0.1;
constexpr double kMaxRateMmS = 0.5;
constexpr double kPeriodS = 0.010;

class CanProcess : public ProcessTest {
 protected:
  /// The example simulator with the daemon's model as the TRUE model, the DBC by absolute path
  /// (the configuration is written into the temp directory) and the test's interface.
  static json canSimConfig() {
    json s = example("sim-vmc-can.json");
    s["model"] = exampleFile("vmc-xyfz-21.json");
    s["settle_ms"] = 500;  // the first writes ramp the offsets in at max_rate
    // The emulated guest's scheduling jitter reaches a cycle period (see docs/can.md).
    s["limits"]["rate_tolerance_ms"] = 10;
    s["transport"]["dbc"] = exampleFile("vmc-can.dbc");
    return s;
  }

  static json canDaemonConfig() {
    json d = example("volcompd-can.json");
    d["model"] = exampleFile("vmc-xyfz-21.json");
    d["transport"]["dbc"] = exampleFile("vmc-can.dbc");
    d["transport"]["interface"] = can::test::interfaceName();
    return d;
  }

  /// Starts the simulator on the test's interface (by --interface) and checks its LISTENING line.
  void startCanSim(const json& config, std::vector<std::string> args = {}) {
    args.insert(args.begin(), {"--interface", can::test::interfaceName()});
    Listening at;
    sim_ = spawnSim(config, args, "sim", at);
    ASSERT_EQ(at.kind, "can");
    ASSERT_EQ(at.device, can::test::interfaceName());
  }
};

// The machine moves along the example raster; the daemon compensates it over CAN for at least
// 400 writes (4 s of 10 ms cycles), then SIGTERM: ramp-out, a final zero write with status 0,
// exit 0.
TEST_F(CanProcess, CompensatesTheMovingMachineAndStopsCleanlyOnSigterm) {
  ASSERT_NO_FATAL_FAILURE(startCanSim(canSimConfig()));
  startDaemon(canDaemonConfig());
  ASSERT_TRUE(waitForSim([](const json& s) { return s["writes"].get<int>() >= 400; }, 45s))
      << daemonLog();
  // The error statistics of compensated running, before the stop ramps the offsets out.
  const json running = simStatus();
  stopDaemon();
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << sim_->stderrText();
  std::cout << "CAN processes, running: " << running.dump() << "\nfinal: " << report.dump()
            << std::endl;

  const double uncompensated = running["rms_uncompensated_um"];
  const double compensated = running["rms_compensated_um"];
  ASSERT_GT(uncompensated, 1.0);  // the machine has a real error to remove
  EXPECT_GE(1.0 - compensated / uncompensated, 0.95)
      << "RMS " << uncompensated << " -> " << compensated << " um";
  EXPECT_EQ(running["limiter_violations"], 0) << running["first_violation"];
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  EXPECT_EQ(report["can"]["malformed_frames"], 0);
  EXPECT_GT(report["can"]["published"].get<int>(), 0);

  const auto rows = record();
  ASSERT_FALSE(rows.empty()) << daemonLog();
  expectWritesWithinLimits(rows, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  std::size_t stop = 0;
  while (stop < rows.size() && !(rows[stop].status & kStopping)) ++stop;
  ASSERT_LT(stop, rows.size()) << "no write with the STOPPING bit";
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
  EXPECT_EQ(rows.back().status, 0U) << "status 0 = inactive";
  for (double o : report["applied_offset_mm"]) EXPECT_EQ(o, 0.0);
}

// Fault injection over CAN: `stall` makes the simulated controller silent for 1 s (socket
// closed: no input frames, writes not received). The daemon sees stale input (fault, offsets
// ramped to zero), the controller's heartbeat watchdog (500 ms) removes the applied offsets by
// itself, and when the node is back the daemon compensates again. Nothing the daemon writes during
// the silence reaches the controller, so the per-write limit is checked on each side of the gap;
// across it the simulator checks the first write against the offsets it then applies.
TEST_F(CanProcess, ASilentControllerIsAFaultAndCompensationResumes) {
  ASSERT_NO_FATAL_FAILURE(startCanSim(canSimConfig()));
  startDaemon(canDaemonConfig());
  ASSERT_TRUE(waitForAppliedOffset(0.005, 30s)) << daemonLog();
  sim_->writeLine("stall 1");
  // Writes arrive again once the node has reopened (a second session).
  ASSERT_TRUE(waitForSim([](const json& s) { return s["sessions"].get<int>() >= 2; }, 20s))
      << daemonLog();
  // Compensating again: 50 more writes (0.5 s), the applied offsets back in.
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50, 30s)) << daemonLog();
  const json resumed = simStatus();
  stopDaemon();
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << sim_->stderrText();
  std::cout << "CAN processes, stall: " << report.dump() << "\nsimulator: " << sim_->stderrText()
            << "daemon: " << daemonLog() << std::endl;
  double largest = 0.0;
  for (double o : resumed["applied_offset_mm"]) largest = std::max(largest, std::abs(o));
  EXPECT_GE(largest, 0.005) << resumed.dump();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["can"]["reopens"], 1);
  EXPECT_GE(report["watchdog_trips"].get<int>(), 1);
  const std::string log = daemonLog();
  // The driver reports stale input as a read error: a transaction-error fault.
  const auto fault = log.find("-> fault: transaction-error");
  ASSERT_NE(fault, std::string::npos) << log;
  EXPECT_NE(log.find("fault -> active", fault), std::string::npos) << log;

  const auto rows = record();
  ASSERT_FALSE(rows.empty());
  std::size_t gap = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > 0.5) gap = i;
  }
  ASSERT_GT(gap, 0U) << "no gap in the writes during the stall";
  const std::vector<WriteRow> before(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(gap));
  const std::vector<WriteRow> after(rows.begin() + static_cast<std::ptrdiff_t>(gap), rows.end());
  expectWritesWithinLimits(before, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  expectWritesWithinLimits(after, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  EXPECT_EQ(rows.back().status, 0U);
}

// The interface goes down (administratively, as `ip link set vcan0 down`) while the daemon
// compensates: its socket reports the network down, a lost link, and nothing can be written.
// Up again: the daemon reconnects with its backoff, reads back the offsets the controller applies
// and continues from them. No write on either side of the gap breaks the limits, and the
// simulator checks the first write after it against what it applies.
TEST_F(CanProcess, InterfaceDownIsALinkLossAndRecoveryDoesNotJump) {
  ASSERT_NO_FATAL_FAILURE(startCanSim(canSimConfig()));
  startDaemon(canDaemonConfig());
  ASSERT_TRUE(waitForAppliedOffset(0.005, 30s)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50, 30s)) << daemonLog();  // compensating for 0.5 s
  const std::string iface = can::test::interfaceName();
  ASSERT_TRUE(can::test::setInterfaceUp(iface, false));
  const bool lost = testutil::waitUntil(
      [&] { return daemonLog().find("-> link lost") != std::string::npos; }, 10s);
  ASSERT_TRUE(can::test::setInterfaceUp(iface, true));
  ASSERT_TRUE(lost) << daemonLog();
  // Compensating again: 50 more writes after the reconnection. (Whether the simulator's own
  // socket noticed the interface going down depends on the timing; the daemon's did.)
  ASSERT_TRUE(waitForMoreWrites(*sim_, 50, 30s)) << daemonLog() << sim_->stderrText();
  stopDaemon();
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << sim_->stderrText();
  std::cout << "CAN processes, interface down: " << report.dump() << "\ndaemon: " << daemonLog()
            << std::endl;
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const std::string log = daemonLog();
  // Reconnected, read back and synchronised: straight back to active, or through starting when
  // the reconnecting cycle's read was older than read_to_write_max_ms by the time its write was
  // due (the emulated guest is often starved that long) and the applied offsets are read again.
  const auto lostAt = log.find("-> link lost");
  ASSERT_NE(lostAt, std::string::npos) << log;
  const bool direct = log.find("link-lost -> active", lostAt) != std::string::npos;
  const auto startingAt = log.find("link-lost -> starting", lostAt);
  const bool throughStarting = startingAt != std::string::npos &&
                               log.find("starting -> active", startingAt) != std::string::npos;
  EXPECT_TRUE(direct || throughStarting) << log;

  const auto rows = record();
  ASSERT_FALSE(rows.empty());
  std::size_t gap = 0;
  double longest = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].tS - rows[i - 1].tS > longest) {
      longest = rows[i].tS - rows[i - 1].tS;
      gap = i;
    }
  }
  ASSERT_GT(gap, 0U);
  EXPECT_GT(longest, 0.05) << "no gap in the writes while the interface was down";
  const std::vector<WriteRow> before(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(gap));
  const std::vector<WriteRow> after(rows.begin() + static_cast<std::ptrdiff_t>(gap), rows.end());
  expectWritesWithinLimits(before, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  expectWritesWithinLimits(after, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  EXPECT_EQ(rows.back().status, 0U);
}

// --probe over CAN: one consistent set of the controller's frames, every signal with its frame,
// DBC name, bit layout, scale and raw value; nothing is sent to the controller.
TEST_F(CanProcess, ProbeShowsEveryFrameAndSignalAndWritesNothing) {
  ASSERT_NO_FATAL_FAILURE(startCanSim(canSimConfig()));
  std::string out;
  ASSERT_EQ(probe(canDaemonConfig(), {}, out), 0) << out;
  EXPECT_NE(out.find("probe       can " + can::test::interfaceName()), std::string::npos) << out;
  for (const char* frame : {"frame 0x100 [8] ", "frame 0x101 [8] ", "frame 0x102 [8] "}) {
    EXPECT_NE(out.find(frame), std::string::npos) << frame << '\n' << out;
  }
  for (const char* signal :
       {"X_Pos 0|28@1- x0.0001", "Y_Pos 28|28@1- x0.0001", "Z_Pos 0|32@1- x0.0001",
        "Enable 32|1@1+", "Homed 33|1@1+", "App_X 0|16@1- x0.0001", "App_Z 32|16@1- x0.0001"}) {
    EXPECT_NE(out.find(signal), std::string::npos) << signal << '\n' << out;
  }
  for (const char* field : {"position.X", "position.Y", "position.Z", "enable", "homed",
                            "applied_offset.X", "applied_offset.Z"}) {
    EXPECT_NE(out.find("    " + std::string(field)), std::string::npos) << field << '\n' << out;
  }
  // A signed signal's raw value as the integer it encodes (the raster runs at Z = -200 mm).
  EXPECT_NE(out.find("raw -2000000"), std::string::npos) << out;
  EXPECT_NE(out.find("-200.0000 mm"), std::string::npos) << out;
  EXPECT_NE(out.find("written     nothing"), std::string::npos) << out;
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << sim_->stderrText();
  EXPECT_EQ(report["writes"], 0) << report.dump();
}

// --test-offset over CAN: the offset goes through the limiter, is read back from the controller's
// applied-offset frame and ramped out; every frame the simulator received is within the limits.
TEST_F(CanProcess, TestOffsetGoesThroughTheLimiterReadsBackAndRampsOut) {
  ASSERT_NO_FATAL_FAILURE(startCanSim(canSimConfig()));
  std::string out;
  ASSERT_EQ(probe(canDaemonConfig(), {"--test-offset", "Y:-5um", "--hold", "0.3"}, out), 0) << out;
  EXPECT_NE(out.find("test-offset: Y -5 um through the limiter"), std::string::npos) << out;
  EXPECT_NE(out.find("read back -5 um (applied_offset.Y), equal to the target"), std::string::npos)
      << out;
  EXPECT_NE(out.find("ramp-out  zero written with status 0"), std::string::npos) << out;
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << sim_->stderrText();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_GT(rows.size(), 3U);
  expectWritesWithinLimits(rows, kMaxOffsetMm, kMaxRateMmS, kPeriodS);
  double smallestY = 0.0;
  for (const WriteRow& row : rows) {
    smallestY = std::min(smallestY, row.offsetMm[1]);
    EXPECT_EQ(row.offsetMm[0], 0.0);
    EXPECT_EQ(row.offsetMm[2], 0.0);
  }
  EXPECT_NEAR(smallestY, -0.005, 1e-9);
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
  EXPECT_EQ(rows.back().status, 0U);
}

}  // namespace
}  // namespace volcomp::e2e
