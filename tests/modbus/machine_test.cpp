#include "volcomp/sim/machine.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "temp_files.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/sim/commands.hpp"
#include "volcomp/sim/path.hpp"

namespace volcomp::sim {
namespace {

loop::OffsetCommand offsets(double x, double y, double z, std::uint16_t heartbeat = 0) {
  loop::OffsetCommand c;
  c.offsetMm = {x, y, z};
  c.heartbeat = heartbeat;
  return c;
}

Machine standing(const Vec3& at, MachineOptions opt = {}, ErrorFunction e = {}) {
  if (!e) e = [](const Vec3&, const MotionDirections&) { return Vec3{}; };
  return Machine(Path::polyline({at}, 1000.0), std::move(e), opt);
}

TEST(SimPath, PolylineAtFeed) {
  // 6000 mm/min = 100 mm/s along (0,0,0) -> (100,0,0) and back (closed): at 0.5 s x = 50, at
  // 1.25 s we are 25 mm into the way back (x = 75), at 2.0 s back at the start.
  const Path p = Path::polyline({{0, 0, 0}, {100, 0, 0}}, 6000.0);
  EXPECT_DOUBLE_EQ(p.lengthMm(), 200.0);
  EXPECT_NEAR(p.at(0.5)[0], 50.0, 1e-9);
  EXPECT_NEAR(p.at(1.25)[0], 75.0, 1e-9);
  EXPECT_NEAR(p.at(2.0)[0], 0.0, 1e-9);
}

TEST(SimPath, ExactStopBrakesAtEveryPoint) {
  // 100 mm/s, 1000 mm/s^2: 0.1 s and 5 mm to reach the feed, 0.9 s of cruise, 0.1 s of braking:
  // 1.1 s per 100 mm segment, at rest at both ends.
  const Path p = Path::polyline({{0, 0, 0}, {100, 0, 0}}, 6000.0).withAcceleration(1000.0);
  EXPECT_NEAR(p.at(0.05)[0], 1.25, 1e-9);
  EXPECT_NEAR(p.at(0.55)[0], 50.0, 1e-9);
  EXPECT_NEAR(p.at(1.05)[0], 100.0 - 1.25, 1e-9);
  EXPECT_NEAR(p.at(1.1)[0], 100.0, 1e-9);
  EXPECT_NEAR(p.at(1.15)[0], 100.0 - 1.25, 1e-9);  // on the way back
  EXPECT_NEAR(p.at(2.2)[0], 0.0, 1e-9);
  // The reversal at x = 100 is one constant deceleration: velocity continuous, |a| <= 1000.
  const double h = 1e-4;
  for (double t = 0.95; t < 1.25; t += 0.001) {
    const double v0 = (p.at(t)[0] - p.at(t - h)[0]) / h, v1 = (p.at(t + h)[0] - p.at(t)[0]) / h;
    EXPECT_LE(std::abs(v1), 100.0 + 1e-6);
    EXPECT_LE(std::abs(v1 - v0) / h, 1000.0 * 1.001) << t;
  }
  // A segment too short for the feed: braking starts halfway (2 mm at 1000 mm/s^2: 2 x 44.7 ms).
  const Path s = Path::polyline({{0, 0, 0}, {2, 0, 0}}, 6000.0).withAcceleration(1000.0);
  EXPECT_NEAR(s.at(std::sqrt(0.002))[0], 1.0, 1e-9);
  EXPECT_NEAR(s.at(2.0 * std::sqrt(0.002))[0], 2.0, 1e-9);
  EXPECT_THROW((void)Path::circle({0, 0, 0}, 10.0, 100.0).withAcceleration(1000.0),
               std::invalid_argument);
  EXPECT_THROW((void)p.withAcceleration(0.0), std::invalid_argument);
}

TEST(SimPath, CircleStaysOnTheCircle) {
  const Path p = Path::circle({100, 50, -20}, 30.0, 3000.0);
  for (double t : {0.0, 0.3, 1.7, 5.55}) {
    const Vec3 q = p.at(t);
    EXPECT_NEAR(std::hypot(q[0] - 100, q[1] - 50), 30.0, 1e-9);
    EXPECT_DOUBLE_EQ(q[2], -20.0);
  }
  // Quarter circle = 47.12 mm at 50 mm/s: 0.9425 s to reach (100, 80).
  const Vec3 q = p.at(2 * M_PI * 30.0 / 4.0 / 50.0);
  EXPECT_NEAR(q[0], 100.0, 1e-9);
  EXPECT_NEAR(q[1], 80.0, 1e-9);
}

TEST(SimPath, RasterZigZagsInsideItsBox) {
  const Path p = Path::raster({0, 0, -10}, {100, 20, -10}, 10.0, 6000.0);
  // Lines y = 0, 10, 20 of 100 mm, two 10 mm steps, return diagonal from (100,20) to (0,0).
  EXPECT_NEAR(p.lengthMm(), 300.0 + 20.0 + std::hypot(100.0, 20.0), 1e-9);
  const auto b = p.bounds();
  EXPECT_EQ(b[0], (Vec3{0, 0, -10}));
  EXPECT_EQ(b[1], (Vec3{100, 20, -10}));
  // After 1.05 s (105 mm): 100 mm along y = 0, then 5 mm up the step: (100, 5).
  EXPECT_NEAR(p.at(1.05)[0], 100.0, 1e-9);
  EXPECT_NEAR(p.at(1.05)[1], 5.0, 1e-9);
}

// A path file is read like every CSV of volcomp: header in any order, unit suffixes, comments.
TEST(SimPath, CsvFileThroughTheSharedReader) {
  volcomp::testing::TempDir dir;
  const std::string file =
      dir.write("path.csv", "# a square in XY\nz,y_um,x\n-10,0,0\n-10,0,100\n-10,50000,100\n");
  const Path p = Path::fromCsv(file, 6000.0);
  // (0,0) -> (100,0) -> (100,50) and back: 100 + 50 + hypot(100, 50).
  EXPECT_NEAR(p.lengthMm(), 150.0 + std::hypot(100.0, 50.0), 1e-9);
  EXPECT_NEAR(p.at(1.25)[1], 25.0, 1e-9);
  EXPECT_DOUBLE_EQ(p.at(0.0)[2], -10.0);
  const std::string bad = dir.write("bad.csv", "x,y,z\n1,2,3\n1,two,3\n");
  try {
    (void)Path::fromCsv(bad, 6000.0);
    FAIL() << "accepted";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "line 3, column y") << e.what();
  }
  EXPECT_THROW((void)Path::fromCsv(dir.write("empty.csv", "x,y,z\n"), 6000.0), config::ConfigError);
}

TEST(SimMachine, PositionSemantics) {
  MachineOptions opt;
  Machine commanded = standing({10, 20, 30}, opt);
  opt.semantics = loop::PositionSemantics::Actual;
  Machine actual = standing({10, 20, 30}, opt);
  for (Machine* m : {&commanded, &actual}) m->onWrite(0.01, offsets(0.1, -0.2, 0.3));
  EXPECT_EQ(commanded.inputs(0.02).positionMm, (Vec3{10, 20, 30}));
  const Vec3 a = actual.inputs(0.02).positionMm;
  EXPECT_NEAR(a[0], 10.1, 1e-12);
  EXPECT_NEAR(a[1], 19.8, 1e-12);
  EXPECT_NEAR(a[2], 30.3, 1e-12);
}

TEST(SimMachine, ChecksEveryWriteAgainstTheLimits) {
  MachineOptions opt;
  opt.limits.maxOffsetMm = {0.05, 0.05, 0.05};
  opt.limits.maxRateMmS = {1.0, 1.0, 1.0};
  opt.limits.rateToleranceS = 0.001;
  opt.limits.quantumMm = {1e-4, 1e-4, 1e-4};
  opt.limits.cycleS = 0.010;
  Machine m = standing({0, 0, 0}, opt);
  m.onSessionStart(0.0);
  // The first write of a session, 1 ms after connecting, may make one limiter step of the
  // writer's 10 ms cycle: up to 1 mm/s * (0.010 + 0.001) + 2e-4 = 0.0112 mm.
  m.onWrite(0.001, offsets(0.0105, 0, 0));
  m.onWrite(0.010, offsets(0.011, 0, 0));
  // Another 0.012 mm in 10 ms: 0.012 > 0.0112 -> rate violation on X.
  m.onWrite(0.020, offsets(0.023, 0, 0));
  // Beyond max_offset (+ one count): 0.0503 > 0.0501 -> offset violation on Y (counted as that,
  // the rate is checked only within max_offset).
  m.onWrite(1.020, offsets(0.023, 0.0503, 0));
  const nlohmann::json r = m.report(1.1);
  EXPECT_EQ(r["writes"], 4);
  EXPECT_EQ(r["limiter_violations"], 2);
  EXPECT_EQ(r["rate_violations"], 1);
  EXPECT_EQ(r["offset_violations"], 1);
  EXPECT_EQ(r["axes"]["X"]["limiter_violations"], 1);
  EXPECT_EQ(r["axes"]["Y"]["limiter_violations"], 1);
  EXPECT_NE(r["first_violation"].get<std::string>().find("axis X"), std::string::npos);
  const auto w = m.writes();
  EXPECT_FALSE(w[0].violation);
  EXPECT_FALSE(w[1].violation);
  EXPECT_TRUE(w[2].violation);
  EXPECT_TRUE(w[3].violation);
}

// The rate check measures the controller's time between the writes it applies: a late cycle
// followed by an on-time one 2 ms later may step by max_rate x 2 ms, not by a whole cycle's step
// (two steps in one period would be 2 x max_rate at the machine).
TEST(SimMachine, StepsAreCheckedAgainstTheControllerTimeBetweenWrites) {
  MachineOptions opt;
  opt.limits.maxRateMmS = {1.0, 1.0, 1.0};
  opt.limits.rateToleranceS = 0.0;
  opt.limits.cycleS = 0.010;
  Machine m = standing({0, 0, 0}, opt);
  m.onSessionStart(0.0);
  m.onWrite(0.010, offsets(0.010, 0, 0));
  m.onWrite(0.018, offsets(0.018, 0, 0));  // 8 ms: 8 um
  m.onWrite(0.020, offsets(0.020, 0, 0));  // 2 ms: 2 um
  EXPECT_EQ(m.report(0.1)["rate_violations"], 0);
  m.onWrite(0.022, offsets(0.030, 0, 0));  // 2 ms: a whole step of 10 um bunched in
  EXPECT_EQ(m.report(0.1)["rate_violations"], 1);
  // More than one step (0.0101 mm > 0.010 mm) in a whole cycle is a violation too.
  m.onWrite(0.032, offsets(0.0401, 0, 0));
  EXPECT_EQ(m.report(0.1)["rate_violations"], 2);
}

// Each axis is checked against its own limits.
TEST(SimMachine, PerAxisLimits) {
  MachineOptions opt;
  opt.limits.maxOffsetMm = {0.05, 0.1, 0.1};
  opt.limits.maxRateMmS = {1.0, 0.5, 1.0};
  opt.limits.rateToleranceS = 0.0;
  opt.limits.cycleS = 0.010;
  Machine m = standing({0, 0, 0}, opt);
  m.onWrite(0.010, offsets(0.010, 0.005, 0.010));
  EXPECT_EQ(m.report(0.1)["limiter_violations"], 0);
  m.onWrite(0.020, offsets(0.020, 0.0111, 0.020));  // Y: 6.1 um > 0.5 mm/s x 10 ms
  EXPECT_EQ(m.report(0.1)["axes"]["Y"]["limiter_violations"], 1);
  EXPECT_EQ(m.report(0.1)["axes"]["X"]["limiter_violations"], 0);
}

// The writer's limiter steps per cycle, so a pause (a stalled daemon, a lost link) allows no
// larger step than one cycle does: resuming with a jump is a violation however long the pause.
TEST(SimMachine, APauseAllowsNoLargerStepThanOneCycle) {
  MachineOptions opt;
  opt.limits.maxRateMmS = {1.0, 1.0, 1.0};
  opt.limits.rateToleranceS = 0.0;
  opt.limits.cycleS = 0.010;
  Machine m = standing({0, 0, 0}, opt);
  m.onSessionStart(0.0);
  m.onWrite(0.010, offsets(0.010, 0, 0));
  // 1 s later: one step (0.010 mm) is fine, two steps (0.020 mm more) are not.
  m.onWrite(1.010, offsets(0.020, 0, 0));
  EXPECT_EQ(m.report(1.1)["rate_violations"], 0);
  m.onWrite(2.010, offsets(0.0401, 0, 0));
  EXPECT_EQ(m.report(2.1)["rate_violations"], 1);
}

// After the controller's heartbeat watchdog moved the offsets, the daemon follows the read-back
// only once it departs by more than one step plus the read-back resolution: up to two steps plus
// that resolution from the applied offset are allowed for the next write, and no more.
TEST(SimMachine, AfterTheWatchdogRampTwoStepsPlusTheReadbackResolutionAreAllowed) {
  MachineOptions opt;
  opt.heartbeatTimeoutS = 0.1;
  opt.watchdogRampMmS = 1.0;
  opt.limits.maxRateMmS = {1.0, 1.0, 1.0};
  opt.limits.rateToleranceS = 0.0;
  opt.limits.cycleS = 0.010;
  opt.initialOffsetMm = {0.03, 0, 0};
  Machine m = standing({0, 0, 0}, opt);
  m.sample(0.0);
  m.onWrite(0.0, offsets(0.03, 0, 0, 1));
  m.onWrite(0.01, offsets(0.03, 0, 0, 2));
  // The heartbeat stops changing: from 0.11 s the ramp removes 1 um per ms.
  for (int i = 1; i <= 115; ++i) m.sample(0.01 + i * 0.001);
  const double applied = m.appliedOffsetMm()[0];
  ASSERT_LT(applied, 0.03 - 1e-3);
  // Two steps (0.020 mm) plus 1e-4 mm above the applied offset: allowed.
  m.onWrite(0.125, offsets(applied + 0.020 + 0.9e-4, 0, 0, 3));
  EXPECT_EQ(m.report(0.13)["rate_violations"], 0);
  // The next write is back to one step: 0.0101 mm more is a violation.
  m.onWrite(0.135, offsets(applied + 0.020 + 0.9e-4 + 0.0101, 0, 0, 4));
  EXPECT_EQ(m.report(0.14)["rate_violations"], 1);
}

TEST(SimMachine, FirstWriteAfterReconnectMustContinueFromTheAppliedOffset) {
  MachineOptions opt;
  opt.limits.maxRateMmS = {0.5, 0.5, 0.5};
  opt.limits.rateToleranceS = 0.0;
  opt.limits.cycleS = 0.01;
  opt.initialOffsetMm = {0.02, 0, 0};  // left applied by an earlier run
  Machine m = standing({0, 0, 0}, opt);
  m.onSessionStart(10.0);
  // Jumping to zero 10 ms after connecting: 0.02 mm > 0.5 mm/s * 0.01 s = 0.005 mm.
  m.onWrite(10.01, offsets(0.0, 0, 0));
  EXPECT_EQ(m.report(10.1)["rate_violations"], 1);
}

TEST(SimMachine, ToolTipErrorWithAndWithoutCompensation) {
  // True error E(q) = (0.010 + 1e-4 x, 0, 0) mm. At x = 100: E = 0.020 mm, uncompensated 20 um.
  // With the exact offset o: x + o + E(x + o) = x -> o = -0.020 / 1.0001 = -0.019998 mm the
  // compensated error is E(q + o) + o = 0. With o = -0.010 it is 0.020 - 1e-6 - 0.010 = 9.999 um.
  ErrorFunction e = [](const Vec3& q, const MotionDirections&) {
    return Vec3{0.010 + 1e-4 * q[0], 0, 0};
  };
  Machine m = standing({100, 0, 0}, {}, e);
  m.sample(0.0);  // before the first write nothing is counted
  EXPECT_EQ(m.report(0.0)["samples"], 0);
  m.onWrite(0.001, offsets(-0.020 / 1.0001, 0, 0));
  m.sample(0.002);
  nlohmann::json r = m.report(0.002);
  EXPECT_NEAR(r["rms_uncompensated_um"].get<double>(), 20.0, 1e-9);
  EXPECT_NEAR(r["rms_compensated_um"].get<double>(), 0.0, 1e-9);
  m.onWrite(0.003, offsets(-0.010, 0, 0));
  m.sample(0.004);
  r = m.report(0.004);
  EXPECT_NEAR(r["max_compensated_um"].get<double>(), 9.999, 1e-9);
  EXPECT_NEAR(r["axes"]["X"]["max_uncompensated_um"].get<double>(), 20.0, 1e-9);
  // RMS over the two samples: sqrt((0^2 + 9.999^2) / 2).
  EXPECT_NEAR(r["rms_compensated_um"].get<double>(), 9.999 / std::sqrt(2.0), 1e-9);
  EXPECT_EQ(r["samples"], 2);
}

TEST(SimMachine, MotionInducedErrorIsWhatTheIdealOffsetOfTheInstantWouldNotLeave) {
  // E(x) = (1e-4 x, 0, 0) mm, X moving at 100 mm/s from 0 to 1000 and back. The ideal offset at x
  // solves o = -1e-4 (x + o): o* = -1e-4 x / 1.0001, which leaves nothing; the offset of a
  // position 1 mm behind leaves E(x + o) + o = 1e-4 mm more.
  ErrorFunction e = [](const Vec3& q, const MotionDirections&) { return Vec3{1e-4 * q[0], 0, 0}; };
  MachineOptions opt;
  opt.limits.cycleS = 0.01;
  Machine m(Path::polyline({{0, 0, 0}, {1000, 0, 0}}, 6000.0), e, opt);
  m.sample(0.0);
  const double ideal = -1e-4 * 500.0 / 1.0001;  // at t = 5 s, x = 500
  m.onWrite(5.0, offsets(ideal, 0, 0));
  m.sample(5.0);
  nlohmann::json r = m.report(5.0);
  EXPECT_NEAR(r["rms_motion_um"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(r["rms_compensated_um"].get<double>(), 0.0, 1e-9);
  // 10 ms later x = 501: the offset of x = 500 is 1 mm behind.
  m.sample(5.01);
  r = m.report(5.01);
  const double lagUm = (1e-4 * (501.0 + ideal) + ideal) * 1000.0;
  EXPECT_NEAR(lagUm, 0.1, 1e-3);
  EXPECT_NEAR(r["max_motion_um"].get<double>(), lagUm, 1e-9);
  EXPECT_NEAR(r["max_compensated_um"].get<double>(), lagUm, 1e-9) << "the model is exact";
  EXPECT_EQ(r["motion_steady_samples"], 2) << "no reversal yet";
  // The reversal at x = 1000 (t = 10 s), seen by the sample at 10.01 s: the three cycles after
  // it are its transient, and so are the three before it (9.995 s; 9.97 s is further away).
  m.sample(9.97);
  m.sample(9.995);
  EXPECT_EQ(m.report(9.995)["motion_steady_samples"], 4) << "steady as far as known at the end";
  m.sample(10.01);
  m.sample(10.02);
  m.sample(10.05);
  r = m.report(10.05);
  EXPECT_EQ(r["samples"], 7);
  EXPECT_EQ(r["motion_steady_samples"], 4);
}

TEST(SimMachine, TheAxesFeelAWriteTheControllerLatencyAfterItArrives) {
  // E(x) = (1e-3, 0, 0) mm everywhere; an offset of -1e-3 removes it. With 4 ms of controller
  // latency the axes keep the old (zero) offset for 4 ms after the write.
  ErrorFunction e = [](const Vec3&, const MotionDirections&) { return Vec3{1e-3, 0, 0}; };
  MachineOptions opt;
  opt.axisLatencyS = 0.004;
  Machine m = standing({10, 0, 0}, opt, e);
  m.onWrite(0.0, offsets(0, 0, 0));
  m.sample(0.001);
  m.onWrite(0.002, offsets(-1e-3, 0, 0));
  EXPECT_EQ(m.inputs(0.0025).appliedOffsetMm[0], -1e-3) << "the register has it at once";
  for (int i = 3; i <= 10; ++i) m.sample(i * 0.001);
  // Samples at 1, 3 .. 10 ms: the axes feel the write from 6 ms on: 1 um at 1, 3, 4 and 5 ms.
  nlohmann::json r = m.report(0.010);
  EXPECT_EQ(r["samples"], 9);
  EXPECT_NEAR(r["rms_compensated_um"].get<double>(), std::sqrt(4.0 / 9.0), 1e-9);
}

// A controller that latches the positions once per 4 ms scan serves them until the next, stamped
// with the latch time (10 us ticks, 16 bits wrapping).
TEST(SimMachine, AScanLatchesThePositionsAndTheTimestampSaysWhen) {
  MachineOptions opt;
  opt.positionScanS = 0.004;
  opt.timestampTickS = 10e-6;
  Machine m(Path::polyline({{0, 0, 0}, {1000, 0, 0}}, 6000.0), ErrorFunction{}, opt);  // 100 mm/s
  m.sample(0.0);
  const loop::AxisSample a = m.inputs(0.0110);
  EXPECT_NEAR(a.positionMm[0], 0.8, 1e-9) << "latched at 8 ms";
  EXPECT_TRUE(a.hasTimestamp);
  EXPECT_EQ(a.timestampTicks, 800);
  EXPECT_DOUBLE_EQ(a.timestampTickS, 10e-6);
  const loop::AxisSample b = m.inputs(0.0119);
  EXPECT_EQ(b.positionMm[0], a.positionMm[0]) << "the same scan";
  EXPECT_EQ(b.timestampTicks, a.timestampTicks);
  const loop::AxisSample c = m.inputs(0.6600);
  EXPECT_NEAR(c.positionMm[0], 66.0, 1e-9);
  EXPECT_EQ(c.timestampTicks, 66000 - 65536) << "wrapped";
  // Without a scan: the positions at the read, stamped then; without a tick: no timestamp.
  Machine fresh(Path::polyline({{0, 0, 0}, {1000, 0, 0}}, 6000.0), ErrorFunction{},
                MachineOptions{});
  fresh.sample(0.0);
  const loop::AxisSample d = fresh.inputs(0.0110);
  EXPECT_NEAR(d.positionMm[0], 1.1, 1e-9);
  EXPECT_FALSE(d.hasTimestamp);
}

TEST(SimMachine, HeartbeatWatchdogRampsTheOffsetsAway) {
  MachineOptions opt;
  opt.heartbeatTimeoutS = 0.1;
  opt.watchdogRampMmS = 1.0;
  Machine m = standing({0, 0, 0}, opt);
  m.sample(0.0);
  m.onWrite(0.0, offsets(0.05, -0.05, 0, 1));
  // Sampled every ms: the ramp starts at the first sample after 0.1 s and removes 1 um per ms.
  for (int i = 1; i <= 120; ++i) m.sample(i * 0.001);
  const Vec3 a = m.appliedOffsetMm();
  EXPECT_NEAR(a[0], 0.05 - 0.020, 1.5e-3);
  EXPECT_NEAR(a[1], -0.05 + 0.020, 1.5e-3);
  EXPECT_EQ(m.report(0.12)["watchdog_trips"], 1);
  for (int i = 121; i <= 200; ++i) m.sample(i * 0.001);
  EXPECT_EQ(m.appliedOffsetMm(), (Vec3{0, 0, 0}));
}

TEST(SimMachine, FreezeHoldsTheRegistersHoldStopsTheMachine) {
  Machine m(Path::polyline({{0, 0, 0}, {100, 0, 0}}, 6000.0),
            [](const Vec3&, const MotionDirections&) { return Vec3{}; }, {});
  m.sample(0.0);
  EXPECT_NEAR(m.inputs(0.1).positionMm[0], 10.0, 1e-9);
  m.freeze(0.1, 0.2);
  EXPECT_NEAR(m.inputs(0.2).positionMm[0], 10.0, 1e-9) << "registers frozen";
  EXPECT_NEAR(m.programmedPositionMm()[0], 20.0, 1e-9) << "the machine moves on";
  EXPECT_NEAR(m.inputs(0.35).positionMm[0], 35.0, 1e-9) << "the freeze has ended";
  m.hold(0.35, 0.1);
  EXPECT_NEAR(m.inputs(0.4).positionMm[0], 35.0, 1e-9);
  EXPECT_NEAR(m.inputs(0.44).positionMm[0], 35.0, 1e-9);
  // The hold ends at 0.45 s: 0.05 s later the axis is 5 mm further.
  EXPECT_NEAR(m.inputs(0.5).positionMm[0], 40.0, 1e-9) << "moving again since 0.45 s";
}

TEST(SimCommands, ParseAndApply) {
  const ScheduledEvent e = parseEvent("2.5:drop-link:1.5");
  EXPECT_DOUBLE_EQ(e.atS, 2.5);
  EXPECT_EQ(e.command.kind, Command::Kind::DropLink);
  EXPECT_DOUBLE_EQ(e.command.durationS, 1.5);
  const Command ex = parseCommand("exception 4 2");
  EXPECT_EQ(ex.kind, Command::Kind::Exception);
  EXPECT_EQ(ex.exceptionCode, 4);
  EXPECT_DOUBLE_EQ(ex.durationS, 2.0);
  EXPECT_FALSE(parseCommand("enable off").on);
  EXPECT_THROW(parseCommand("explode"), std::invalid_argument);
  EXPECT_THROW(parseCommand("exception 12"), std::invalid_argument);
  EXPECT_THROW(parseCommand("stall -1"), std::invalid_argument);
  EXPECT_THROW(parseCommand("enable maybe"), std::invalid_argument);
  EXPECT_THROW(parseEvent("drop-link"), std::invalid_argument);

  Machine m = standing({0, 0, 0});
  EXPECT_TRUE(applyCommand(m, 1.0, parseCommand("stall 0.5")));
  EXPECT_TRUE(m.transportFault(1.2).stall);
  EXPECT_FALSE(m.transportFault(1.6).stall);
  EXPECT_TRUE(applyCommand(m, 1.0, parseCommand("exception 3")));
  EXPECT_EQ(m.transportFault(100.0).exceptionCode, 3) << "no duration: until resume";
  EXPECT_TRUE(applyCommand(m, 2.0, parseCommand("resume")));
  EXPECT_EQ(m.transportFault(2.0).exceptionCode, 0);
  EXPECT_TRUE(applyCommand(m, 2.0, parseCommand("homed off")));
  EXPECT_FALSE(m.inputs(2.0).homed);
  EXPECT_FALSE(applyCommand(m, 2.0, parseCommand("quit")));
}

// A PLC's watchdog counts from power-up: offsets left applied with no daemon writing are removed
// too. A garbled read-back changes what the X read-back reports, not what is applied.
TEST(SimMachine, WatchdogRemovesLeftOverOffsetsAndGarbleOnlyChangesTheReadBack) {
  MachineOptions opt;
  opt.heartbeatTimeoutS = 0.1;
  opt.watchdogRampMmS = 1.0;
  opt.initialOffsetMm = {0.15, 0, 0};
  Machine m = standing({0, 0, 0}, opt);
  for (int i = 0; i <= 300; ++i) m.sample(i * 0.001);
  EXPECT_EQ(m.appliedOffsetMm()[0], 0.0);
  EXPECT_EQ(m.report(0.3)["watchdog_trips"], 1);
  EXPECT_TRUE(applyCommand(m, 0.3, parseCommand("garble-readback 150 0.5")));
  EXPECT_DOUBLE_EQ(m.inputs(0.4).appliedOffsetMm[0], 150.0);
  EXPECT_EQ(m.appliedOffsetMm()[0], 0.0);
  EXPECT_DOUBLE_EQ(m.inputs(0.9).appliedOffsetMm[0], 0.0);
}

// The reply faults: the next N writes applied but answered late or never, and a
// client stopped before the answer to its next read. Each is consumed by the request it hits.
TEST(SimCommands, ReplyFaultsAreConsumedOneWriteAtATime) {
  const Command late = parseCommand("late-reply 0.08 2");
  EXPECT_EQ(late.kind, Command::Kind::LateReply);
  EXPECT_DOUBLE_EQ(late.durationS, 0.08);
  EXPECT_EQ(late.count, 2);
  EXPECT_EQ(parseCommand("no-reply").count, 1);
  const Command pause = parseCommand("pause-client 4242 1.5");
  EXPECT_EQ(pause.pid, 4242);
  EXPECT_DOUBLE_EQ(pause.durationS, 1.5);
  EXPECT_TRUE(parseCommand("ack on").on);
  EXPECT_EQ(parseEvent("2:late-reply:0.1:3").command.count, 3);
  EXPECT_THROW(parseCommand("late-reply"), std::invalid_argument);
  EXPECT_THROW(parseCommand("no-reply 0"), std::invalid_argument);
  EXPECT_THROW(parseCommand("pause-client 12"), std::invalid_argument);

  Machine m = standing({0, 0, 0});
  applyCommand(m, 1.0, late);
  applyCommand(m, 1.0, parseCommand("no-reply 1"));
  EXPECT_TRUE(m.takeWriteReply().drop);  // the dropped reply comes first
  EXPECT_DOUBLE_EQ(m.takeWriteReply().delayS, 0.08);
  EXPECT_DOUBLE_EQ(m.takeWriteReply().delayS, 0.08);
  const WriteReply normal = m.takeWriteReply();
  EXPECT_FALSE(normal.drop);
  EXPECT_EQ(normal.delayS, 0.0);
  applyCommand(m, 1.0, pause);
  EXPECT_EQ(m.takeClientPause().pid, 4242);
  EXPECT_EQ(m.takeClientPause().pid, 0);
  applyCommand(m, 1.0, parseCommand("ack on"));
  EXPECT_TRUE(m.inputs(1.0).hasFaultAck);
  EXPECT_TRUE(m.inputs(1.0).faultAck);
  const nlohmann::json r = m.report(2.0);
  EXPECT_EQ(r["late_replies"], 2);
  EXPECT_EQ(r["replies_dropped"], 1);
  EXPECT_EQ(r["client_pauses"], 1);
}

}  // namespace
}  // namespace volcomp::sim
