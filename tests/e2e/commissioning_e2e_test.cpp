// Commissioning against the simulated machine, as processes: every example pair (simulator
// configuration + daemon configuration, as shipped in config/examples, only the port or the
// pseudo-terminal and absolute model paths filled in) runs together with 0 limiter violations;
// `volcompd --probe` reads one sample and writes nothing; `--test-offset X:5um` writes one small
// offset through the limiter, reads it back and ramps it out; over Modbus TCP and RTU.

#include <gtest/gtest.h>

#include <string>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

struct Pair {
  const char* sim;
  const char* daemon;
};

class Commissioning : public ProcessTest, public ::testing::WithParamInterface<Pair> {
 protected:
  // The shipped simulator configuration with its model path made absolute.
  static json shippedSim(const std::string& name, int settleMs = 500) {
    json s = example(name);
    s["model"] = exampleFile(s["model"].get<std::string>());
    s["settle_ms"] = settleMs;
    return s;
  }

  // The shipped daemon configuration pointed at the simulator, its model path made absolute.
  static json shippedDaemon(const std::string& name, const Listening& at) {
    json d = example(name);
    return daemonConfig(at, exampleFile(d["model"].get<std::string>()), name);
  }
};

TEST_P(Commissioning, TheExamplePairRunsWithoutLimiterViolations) {
  const Pair pair = GetParam();
  const json sim = shippedSim(pair.sim);
  const Listening at = startSim(sim, {"--port", "0"});
  ASSERT_FALSE(at.kind.empty());
  const json daemon = shippedDaemon(pair.daemon, at);
  startDaemon(daemon);
  ASSERT_TRUE(waitForAppliedOffset(0.003)) << daemonLog();
  ASSERT_TRUE(waitForMoreWrites(*sim_, 150)) << daemonLog();
  // The error statistics of compensated running: after the stop the machine runs uncompensated
  // until the simulator quits, for as long as the exit takes (longer on a loaded machine).
  const json running = simStatus();
  ASSERT_TRUE(running.is_object());
  stopDaemon();
  const json report = finishSim();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_LE(running["rms_compensated_um"].get<double>(),
            0.2 * running["rms_uncompensated_um"].get<double>())
      << running.dump();
  const auto rows = record();
  ASSERT_GT(rows.size(), 150U);
  expectWritesWithinLimits(rows, daemon["limiter"]["max_offset_mm"].get<double>(),
                           daemon["limiter"]["max_rate_mm_s"].get<double>(),
                           daemon["cycle_period_ms"].get<double>() / 1000.0);
  // The simulator checks against the daemon's cycle: the pair must agree on it.
  EXPECT_EQ(sim["limits"]["cycle_ms"], daemon["cycle_period_ms"]);
}

TEST_P(Commissioning, ProbeReadsOneSampleAndWritesNothing) {
  const Pair pair = GetParam();
  const Listening at = startSim(shippedSim(pair.sim), {"--port", "0"});
  ASSERT_FALSE(at.kind.empty());
  std::string out;
  ASSERT_EQ(probe(shippedDaemon(pair.daemon, at), {}, out), 0) << out;
  EXPECT_NE(out.find("probe       modbus-" + at.kind), std::string::npos) << out;
  EXPECT_NE(out.find("one FC03 of holding 0-13"), std::string::npos) << out;
  // Every decoded value with its register, type, order, scale and raw bytes.
  for (const char* field : {"position.X", "position.Y", "position.Z", "enable", "homed", "sequence",
                            "applied_offset.X", "applied_offset.Z"}) {
    EXPECT_NE(out.find("  " + std::string(field)), std::string::npos) << field << '\n' << out;
  }
  EXPECT_NE(out.find("holding 0-1 int32 ABCD x10000"), std::string::npos) << out;
  EXPECT_NE(out.find("holding 6 bit 0"), std::string::npos) << out;
  EXPECT_NE(out.find("raw "), std::string::npos) << out;
  EXPECT_NE(out.find("written     nothing"), std::string::npos) << out;
  const json report = finishSim();
  EXPECT_EQ(report["writes"], 0) << report.dump();
}

TEST_P(Commissioning, TestOffsetGoesThroughTheLimiterReadsBackAndRampsOut) {
  const Pair pair = GetParam();
  const Listening at = startSim(shippedSim(pair.sim), {"--port", "0"});
  ASSERT_FALSE(at.kind.empty());
  const json daemon = shippedDaemon(pair.daemon, at);
  std::string out;
  ASSERT_EQ(probe(daemon, {"--test-offset", "X:5um", "--hold", "0.3"}, out), 0) << out;
  EXPECT_NE(out.find("test-offset: X +5 um through the limiter"), std::string::npos) << out;
  EXPECT_NE(out.find("read back +5 um (applied_offset.X), equal to the target"), std::string::npos)
      << out;
  EXPECT_NE(out.find("ramp-out  zero written with status 0"), std::string::npos) << out;
  const json report = finishSim();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = record();
  ASSERT_GT(rows.size(), 3U);
  expectWritesWithinLimits(rows, daemon["limiter"]["max_offset_mm"].get<double>(),
                           daemon["limiter"]["max_rate_mm_s"].get<double>(),
                           daemon["cycle_period_ms"].get<double>() / 1000.0);
  double largestX = 0.0;
  for (const WriteRow& row : rows) {
    largestX = std::max(largestX, row.offsetMm[0]);
    EXPECT_EQ(row.offsetMm[1], 0.0);
    EXPECT_EQ(row.offsetMm[2], 0.0);
  }
  EXPECT_NEAR(largestX, 0.005, 1e-9);
  EXPECT_EQ(largestAbs(rows.back().offsetMm), 0.0);
  EXPECT_EQ(rows.back().status, 0U);
}

TEST_P(Commissioning, TestOffsetBeyondTheLimiterIsRefusedBeforeConnecting) {
  const Pair pair = GetParam();
  const Listening at = startSim(shippedSim(pair.sim), {"--port", "0"});
  ASSERT_FALSE(at.kind.empty());
  std::string out;
  EXPECT_EQ(probe(shippedDaemon(pair.daemon, at), {"--test-offset", "Z:0.5mm"}, out), 2) << out;
  EXPECT_NE(out.find("beyond limiter.max_offset_mm (100 um)"), std::string::npos) << out;
  EXPECT_EQ(finishSim()["writes"], 0);
}

INSTANTIATE_TEST_SUITE_P(ExamplePairs, Commissioning,
                         ::testing::Values(Pair{"sim-vmc.json", "volcompd-modbus-tcp.json"},
                                           Pair{"sim-vmc-rtu.json", "volcompd-modbus-rtu.json"}),
                         [](const ::testing::TestParamInfo<Pair>& param) {
                           return std::string(param.index == 0 ? "ModbusTcp" : "ModbusRtu");
                         });

}  // namespace
}  // namespace volcomp::e2e
