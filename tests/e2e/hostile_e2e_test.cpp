// Whole processes against a hostile controller: volcompd talks to volcomp-sim through
// HostileModbusPeer, which answers wrongly in every way a Modbus TCP server can (wrong transaction
// or unit id, wrong function, truncated, oversized, trailing garbage, random bytes, every
// exception code, silence). The daemon must never crash, never write a value past the limiter
// (the simulator's record of every write that reached it is checked), report the fault, and
// compensate again once the peer behaves.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "hostile_modbus_peer.hpp"
#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

using Mode = HostileModbusPeer::Mode;

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
    ++n;
  }
  return n;
}

class Hostile : public ProcessTest {
 protected:
  static constexpr double kMaxOffsetMm = 0.1;
  static constexpr double kMaxRateMmS = 0.5;
  static constexpr double kPeriodS = 0.010;  // cycle_period_ms of volcompd-modbus-tcp.json
  static constexpr double kWatchdogS = 0.5;  // heartbeat_timeout_ms of sim-vmc.json

  /// The simulator (with the daemon's limits, applying `initialOffsetMm` on every axis at start)
  /// and a peer in front of it in `mode`.
  void startPeer(Mode mode, double initialOffsetMm = 0.0) {
    json sim = simConfig(exampleFile("vmc-xyfz-21.json"), 0);
    sim["initial_offset_mm"] = {initialOffsetMm, initialOffsetMm, initialOffsetMm};
    sim["limits"]["max_offset_mm"] = kMaxOffsetMm;
    sim["limits"]["max_rate_mm_s"] = kMaxRateMmS;
    const Listening at = startSim(sim, {"--port", "0"});
    ASSERT_EQ(at.kind, "tcp");
    seed_ = std::random_device{}();
    std::cerr << "hostile peer seed " << seed_ << '\n';
    peer_ = std::make_unique<HostileModbusPeer>(at.port, seed_, mode);
    json daemon =
        daemonConfig(Listening{"tcp", peer_->port(), ""}, exampleFile("vmc-xyfz-21.json"));
    daemon["limiter"]["max_offset_mm"] = kMaxOffsetMm;
    daemon["accept_model_beyond_max_offset"] = true;  // the model exceeds max_offset on purpose
    daemon["limiter"]["max_rate_mm_s"] = kMaxRateMmS;
    startDaemon(daemon);
  }

  /// Waits until the daemon has entered the active state `count` times in all.
  bool waitForActive(std::size_t count, std::chrono::milliseconds timeout = 20s) {
    return testutil::waitUntil([&] { return occurrences(daemonLog(), "-> active") >= count; },
                               timeout);
  }

  /// Lets the peer misbehave in `mode` until the daemon has sent it `requests` more requests or
  /// made `connections` more connections, whichever comes first.
  void misbehave(Mode mode, std::uint64_t requests, std::uint64_t connections) {
    SCOPED_TRACE(HostileModbusPeer::name(mode));
    const std::uint64_t requestsBefore = peer_->requests();
    const std::uint64_t connectionsBefore = peer_->connections();
    peer_->setMode(mode);
    EXPECT_TRUE(testutil::waitUntil(
        [&] {
          return peer_->requests() >= requestsBefore + requests ||
                 peer_->connections() >= connectionsBefore + connections;
        },
        20s))
        << daemonLog();
    peer_->setMode(Mode::PassThrough);
    ASSERT_TRUE(daemon_->running()) << daemonLog();
  }

  void TearDown() override {
    peer_.reset();
    ProcessTest::TearDown();
  }

  std::uint32_t seed_ = 0;
  std::unique_ptr<HostileModbusPeer> peer_;
};

TEST_F(Hostile, EveryWayOfAnsweringWronglyFaultsSafelyAndRecovers) {
  startPeer(Mode::PassThrough);
  ASSERT_TRUE(waitForActive(1)) << daemonLog();
  ASSERT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  std::size_t activations = occurrences(daemonLog(), "-> active");
  // A reply from another unit id is not a fault: libmodbus (3.1.6, Debian 12) checks a TCP
  // reply's transaction and protocol ids but not its unit id, and the Modbus TCP specification
  // leaves the unit id to gateways (a server addressed by its IP address answers whatever unit
  // id it is asked for). The data is the right server's here, so the daemon keeps compensating,
  // within the limits like everywhere else. (Over RTU the unit id is checked.)
  misbehave(Mode::WrongUnitId, 40, 3);
  EXPECT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  activations = occurrences(daemonLog(), "-> active");
  for (const Mode mode :
       {Mode::WrongTransactionId, Mode::WrongFunction, Mode::Truncated, Mode::Oversized,
        Mode::TrailingGarbage, Mode::RandomBytes, Mode::Exception, Mode::Silent}) {
    SCOPED_TRACE(HostileModbusPeer::name(mode));
    // 300 requests in Exception mode: more than 256, so every code is answered at least once.
    misbehave(mode, mode == Mode::Exception ? 300 : 40, 3);
    // Recovery: active again, and compensating.
    EXPECT_TRUE(waitForActive(activations + 1)) << daemonLog();
    activations = occurrences(daemonLog(), "-> active");
    EXPECT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  }
  const json report = finishSim();
  stopDaemon();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const std::vector<WriteRow> rows = record();
  ASSERT_GT(rows.size(), 100U);
  expectWritesWithinLimits(rows, kMaxOffsetMm, kMaxRateMmS, kPeriodS, kWatchdogS);
  std::size_t faults = 0;
  for (const WriteRow& row : rows) faults += (row.status & kFault) != 0 ? 1 : 0;
  EXPECT_GT(faults, 0U) << "the faults were reported to the controller";
}

// Writes held up on their way (every other one 8 ms, a congested gateway) while the offsets ramp
// at max_rate from -0.09 mm left over to the model's few micrometres (about 20 cycles): the held
// write reaches the simulator about 2 ms before the next one, sent on time. The step after it
// must be limited by the time since its reply, not since it was sent, or the controller applies
// two steps within a few milliseconds (the simulator's check counts the time between the writes
// it applied, with 5 ms of tolerance).
TEST_F(Hostile, WritesHeldUpOnTheirWayAreNotBunchedWithTheNext) {
  startPeer(Mode::HeldUp, -0.09);
  ASSERT_TRUE(waitForActive(1)) << daemonLog();
  ASSERT_TRUE(waitForSim(
      [](const json& s) {
        double largest = 0.0;
        for (double o : s["applied_offset_mm"]) largest = std::max(largest, std::abs(o));
        return largest < 0.02;
      },
      20s))
      << daemonLog();
  const json report = finishSim();
  stopDaemon();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const std::vector<WriteRow> rows = record();
  ASSERT_GT(rows.size(), 20U);
  expectWritesWithinLimits(rows, kMaxOffsetMm, kMaxRateMmS, kPeriodS, kWatchdogS);
}

// A server that accepts the connection and never answers, from the start: the daemon keeps
// trying without crashing or writing anything, and starts compensating once it answers.
TEST_F(Hostile, AServerThatNeverAnswersIsSurvivedUntilItDoes) {
  startPeer(Mode::Silent);
  ASSERT_TRUE(testutil::waitUntil([&] { return peer_->connections() >= 3; }, 20s)) << daemonLog();
  EXPECT_TRUE(daemon_->running()) << daemonLog();
  EXPECT_EQ(occurrences(daemonLog(), "-> active"), 0U) << daemonLog();
  peer_->setMode(Mode::PassThrough);
  EXPECT_TRUE(waitForActive(1)) << daemonLog();
  EXPECT_TRUE(waitForAppliedOffset(0.005)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  expectWritesWithinLimits(record(), kMaxOffsetMm, kMaxRateMmS, kPeriodS, kWatchdogS);
}

}  // namespace
}  // namespace volcomp::e2e
