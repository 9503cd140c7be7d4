// Latency compensation with whole processes: volcompd against volcomp-sim over Modbus TCP, the
// same model on both sides (config/examples/vmc-xyfz-21.json), X, Y and Z moving together at
// 400 mm/s along a body diagonal and back. Runs with latency compensation off and on alternate
// (both see the same machine load); the medians of three each are compared. Asserted: the
// steady-motion part of the motion-induced error (the simulator's error minus that of the ideal
// zero-latency offset, outside the cycles just after a reversal) falls by a robust margin, the
// whole motion-induced error does not grow beyond its run-to-run spread, and no write breaks the
// limits.

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

class LatencyCompensation : public ProcessTest {
 protected:
  json runOnce(bool enabled, int run) {
    const std::string model = exampleFile("vmc-xyfz-21.json");
    json sim = simConfig(model);
    sim["path"] = {{"type", "points"},
                   {"feed_mm_min", 24000},
                   {"points", {{100, 100, -300}, {750, 400, -100}}}};
    const Listening at = startSim(sim, {"--port", "0", "--duration", "60"});
    EXPECT_EQ(at.kind, "tcp");
    json daemon = daemonConfig(at, model);
    daemon["latency_compensation"] = {{"enabled", enabled}, {"controller_latency_ms", 0}};
    startDaemon(daemon);
    // A number of samples, not of seconds: a loaded machine (or a sanitizer build) samples less
    // often than every tick.
    EXPECT_TRUE(
        waitForSim([](const json& s) { return s["motion_steady_samples"].get<int>() > 1100; }, 50s))
        << daemonLog();
    const json report = finishSim();
    EXPECT_TRUE(report.is_object()) << daemonLog();
    stopDaemon();
    std::cerr << "run " << run << (enabled ? " on " : " off") << ": motion-induced RMS "
              << report.value("rms_motion_um", -1.0) << " um, steady "
              << report.value("rms_motion_steady_um", -1.0) << " um, residual "
              << report.value("rms_compensated_um", -1.0) << " um\n";
    return report;
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST_F(LatencyCompensation, CutsTheSteadyMotionErrorAt400MmSWithinTheLimits) {
  std::vector<double> steadyOff, steadyOn, motionOff, motionOn;
  for (int run = 0; run < 3; ++run) {
    for (const bool enabled : {false, true}) {
      const json r = runOnce(enabled, run);
      ASSERT_TRUE(r.is_object());
      EXPECT_EQ(r["limiter_violations"], 0) << r["first_violation"];
      EXPECT_EQ(r["sessions"], 1);
      ASSERT_GT(r["motion_steady_samples"].get<int>(), 1000) << r.dump();
      (enabled ? steadyOn : steadyOff).push_back(r["rms_motion_steady_um"].get<double>());
      (enabled ? motionOn : motionOff).push_back(r["rms_motion_um"].get<double>());
    }
  }
  // Measured on the 2-vCPU VM (docs/daemon.md "Latency compensation"): steady part 0.12 um off,
  // 0.074 um on (medians of 5), of which 0.057 um is the floor both share (the 0.1 um register
  // count); the whole is dominated by the two reversal transients, whose size depends on where
  // the turn falls in the cycle: 0.30-0.40 um in either mode.
  EXPECT_LT(median(steadyOn), 0.85 * median(steadyOff));
  EXPECT_LT(median(motionOn), 1.3 * median(motionOff));
}

}  // namespace
}  // namespace volcomp::e2e
