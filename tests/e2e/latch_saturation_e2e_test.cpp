// Whole processes, the loop's latch and saturation rules, seen on the wire (the simulator's
// record):
// - sustained saturation: a model asking for more than max_offset for longer than the thresholds
//   gives a warning naming the axis and the requested value, the SATURATED bit, then the fault
//   sustained-limit (code 7) with ramp-out, and 0 limiter violations;
// - the fault latch: a stale-input fault stays (FAULT + LATCHED, offsets at zero) after its cause
//   is gone, until the controller acknowledges it with its fault-ack bit.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

constexpr unsigned kSaturated = 1u << 9;
constexpr unsigned kLatched = 1u << 10;

class LatchSaturation : public ProcessTest {
 protected:
  /// Simulator and daemon configurations with the fault-ack bit mapped (bit 2 of the flags
  /// register) on both sides.
  void configure(const std::string& model, double maxOffsetMm) {
    model_ = model;
    maxOffsetMm_ = maxOffsetMm;
    sim_cfg_ = simConfig(model, 0);
    sim_cfg_["limits"]["max_offset_mm"] = maxOffsetMm;
    sim_cfg_["limits"]["max_rate_mm_s"] = kMaxRateMmS;
    sim_cfg_["heartbeat_timeout_ms"] = 0;
    sim_cfg_["transport"]["registers"]["fault_ack"] = {{"address", 6}, {"bit", 2}};
  }
  json daemonFor(const Listening& at) const {
    json d = daemonConfig(at, model_);
    d["limiter"]["max_offset_mm"] = maxOffsetMm_;
    d["accept_model_beyond_max_offset"] = true;  // the model exceeds max_offset on purpose
    d["limiter"]["max_rate_mm_s"] = kMaxRateMmS;
    d["transport"]["registers"]["fault_ack"] = {{"address", 6}, {"bit", 2}};
    return d;
  }

  static constexpr double kMaxRateMmS = 0.05;
  std::string model_;
  double maxOffsetMm_ = 0.1;
  json sim_cfg_;
};

/// Index of the first row at or after `from` whose status has `bit`, or rows.size().
std::size_t firstWith(const std::vector<WriteRow>& rows, unsigned bit, std::size_t from = 0) {
  for (std::size_t i = from; i < rows.size(); ++i) {
    if ((rows[i].status & bit) != 0) return i;
  }
  return rows.size();
}

// The example model x8 asks for up to ~115 um with max_offset 20 um: the clamp holds. After
// 0.3 s the warning (axis and requested value) and SATURATED; after 1 s the fault sustained-limit
// ramps the offsets to zero at max_rate, monotonically, and keeps them there (latched).
TEST_F(LatchSaturation, SustainedSaturationWarnsThenFaultsAndRampsOut) {
  configure(writeJson("model-x8.json", scaledModel(example("vmc-xyfz-21.json"), 8.0)), 0.020);
  const Listening at = startSim(sim_cfg_, {"--port", "0"});
  json d = daemonFor(at);
  d["limiter"]["saturation_warning_ms"] = 300;
  d["limiter"]["saturation_fault_ms"] = 1000;
  startDaemon(d);
  ASSERT_TRUE(daemon_->waitForStderr("fault: sustained-limit", 20s)) << daemonLog();
  ASSERT_TRUE(waitForSim(
      [](const json& s) {
        return largestAbs(s["applied_offset_mm"].get<std::array<double, 3>>()) == 0.0;
      },
      10s))
      << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 20)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  expectWritesWithinLimits(rows, maxOffsetMm_, kMaxRateMmS, 0.010);

  const std::string log = daemonLog();
  const auto warning = log.find("limiter: the clamp has held axis");
  ASSERT_NE(warning, std::string::npos) << log;
  EXPECT_NE(log.find("the model asks for", warning), std::string::npos) << log;
  EXPECT_LT(warning, log.find("fault: sustained-limit")) << "the warning comes first";

  const std::size_t saturated = firstWith(rows, kSaturated);
  const std::size_t fault = firstWith(rows, kFault);
  ASSERT_LT(saturated, rows.size());
  ASSERT_LT(fault, rows.size());
  EXPECT_LT(saturated, fault);
  EXPECT_EQ(faultCodeOf(rows[fault].status), 7U);
  EXPECT_TRUE(rows[fault].status & kLatched);
  // The clamp held for ~0.7 s between the warning and the fault (~70 writes).
  EXPECT_GE(rows[fault].tS - rows[saturated].tS, 0.6);
  // Ramp-out: every axis moves towards zero, never away, and stays at zero.
  for (std::size_t i = fault + 1; i < rows.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(rows[i].offsetMm[k]), std::abs(rows[i - 1].offsetMm[k]) + 1e-12);
    }
    EXPECT_EQ(faultCodeOf(rows[i].status), 7U);
  }
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
}

// Frozen registers (life counter standing) for 0.8 s: fault stale-input (code 1) after the
// 500 ms stale timeout. The registers move again, yet the fault stays latched (FAULT + LATCHED,
// offsets ramped to zero) until the controller pulses its fault-ack bit; then the offsets ramp
// back in.
TEST_F(LatchSaturation, LatchedFaultStaysUntilTheControllerAcknowledges) {
  configure(exampleFile("vmc-xyfz-21.json"), 0.1);
  const Listening at = startSim(sim_cfg_, {"--port", "0"});
  startDaemon(daemonFor(at));
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  sim_->writeLine("freeze 0.8");
  ASSERT_TRUE(daemon_->waitForStderr("fault: stale-input", 10s)) << daemonLog();
  // Long after the freeze: still latched, offsets at zero.
  ASSERT_TRUE(waitForSim(
      [](const json& s) {
        return largestAbs(s["applied_offset_mm"].get<std::array<double, 3>>()) == 0.0;
      },
      10s))
      << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 100)) << daemonLog();
  const json latched = simStatus();
  EXPECT_EQ(largestAbs(latched["applied_offset_mm"].get<std::array<double, 3>>()), 0.0);
  sim_->writeLine("ack on");
  ASSERT_TRUE(daemon_->waitForStderr("latched fault acknowledged", 10s)) << daemonLog();
  sim_->writeLine("ack off");
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  expectWritesWithinLimits(rows, maxOffsetMm_, kMaxRateMmS, 0.010);
  const std::size_t fault = firstWith(rows, kFault);
  ASSERT_LT(fault, rows.size());
  EXPECT_EQ(faultCodeOf(rows[fault].status), 1U);
  // From the fault to the acknowledge: FAULT + LATCHED with the stale-input code on every write,
  // also the ~100 written after the registers moved again.
  std::size_t end = fault;
  while (end < rows.size() && (rows[end].status & kFault)) {
    EXPECT_TRUE(rows[end].status & kLatched) << "t=" << rows[end].tS;
    EXPECT_EQ(faultCodeOf(rows[end].status), 1U);
    ++end;
  }
  ASSERT_LT(end, rows.size());
  EXPECT_GE(rows[end].tS - rows[fault].tS, 1.0) << "stayed latched after the freeze ended";
  EXPECT_EQ(largestAbs(rows[end - 1].offsetMm), 0.0);
  EXPECT_TRUE(rows.back().status & kActive);
  EXPECT_FALSE(rows.back().status & kLatched);
}

// Per-axis limits on both sides: the example model x8 asks for more than each axis's band; every
// write stays inside its axis's band and moves each axis no faster than its own rate, per the
// simulator (which knows the same per-axis limits) and per the test's own check of the record.
TEST_F(LatchSaturation, PerAxisLimitsHoldOnTheWire) {
  configure(writeJson("model-x8.json", scaledModel(example("vmc-xyfz-21.json"), 8.0)), 0.030);
  const json maxOffset = {{"X", 0.030}, {"Y", 0.020}, {"Z", 0.010}};
  const json maxRate = {{"X", 0.05}, {"Y", 0.03}, {"Z", 0.02}};
  sim_cfg_["limits"]["max_offset_mm"] = maxOffset;
  sim_cfg_["limits"]["max_rate_mm_s"] = maxRate;
  const Listening at = startSim(sim_cfg_, {"--port", "0"});
  json d = daemonFor(at);
  d["limiter"]["max_offset_mm"] = maxOffset;
  d["accept_model_beyond_max_offset"] = true;  // the model exceeds max_offset on purpose
  d["limiter"]["max_rate_mm_s"] = maxRate;
  d["limiter"]["saturation_fault_ms"] = 0;
  startDaemon(d);
  ASSERT_TRUE(waitForMoreWrites(*sim_, 200)) << daemonLog();
  const json report = finishSim();
  stopDaemon();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_GT(rows.size(), 150U);
  const char* names[] = {"X", "Y", "Z"};
  bool reachedABand = false;
  for (std::size_t k = 0; k < 3; ++k) {
    const double band = maxOffset[names[k]].get<double>();
    const double step = maxRate[names[k]].get<double>() * 0.010 + kQuantumMm + 1e-9;
    double largest = 0.0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      largest = std::max(largest, std::abs(rows[i].offsetMm[k]));
      ASSERT_LE(std::abs(rows[i].offsetMm[k]), band + 0.5 * kQuantumMm + 1e-9)
          << names[k] << " write " << i;
      if (i > 0) {
        ASSERT_LE(std::abs(rows[i].offsetMm[k] - rows[i - 1].offsetMm[k]), step)
            << names[k] << " write " << i;
      }
    }
    if (largest >= band - kQuantumMm) reachedABand = true;
  }
  EXPECT_TRUE(reachedABand) << "no axis reached its own band";
}

}  // namespace
}  // namespace volcomp::e2e
