// Whole processes: volcompd compensating volcomp-sim's machine with the SAME error model on both
// sides (config/examples/vmc-xyfz-21.json), over Modbus TCP and RTU, with both position
// semantics. With a perfect model the only residuals are the register quantisation (0.1 um),
// the one-cycle lag of the offsets behind the motion (6 m/min = 100 mm/s moves 1 mm per 10 ms
// cycle, over which the model changes by well under 1 um) and the direction tracker's
// hysteresis at reversals: the RMS error must fall by at least 95 %, on every axis.

#include <cmath>
#include <ostream>
#include <string>
#include <tuple>

#include "process_fixture.hpp"

namespace volcomp::e2e {
namespace {

struct Case {
  const char* transport;  // "tcp" or "rtu"
  const char* semantics;  // "commanded" or "actual"
};

// Readable test names in CTest ("GetParam() = tcp/actual").
void PrintTo(const Case& c, std::ostream* out) {
  *out << c.transport << '/' << c.semantics;
}

class Compensation : public ProcessTest, public ::testing::WithParamInterface<Case> {};

/// RMS of the samples between two cumulative reports: n2*rms2^2 - n1*rms1^2 is the sum of
/// squares of the samples taken in between.
double rmsBetween(const json& early, const json& late) {
  const double n1 = early["samples"].get<double>();
  const double n2 = late["samples"].get<double>();
  const double r1 = early["rms_compensated_um"].get<double>();
  const double r2 = late["rms_compensated_um"].get<double>();
  return std::sqrt(std::max(0.0, n2 * r2 * r2 - n1 * r1 * r1) / (n2 - n1));
}

TEST_P(Compensation, SameModelRemovesAtLeast95PercentWithoutDriftOrOscillation) {
  const Case c = GetParam();
  const bool rtu = std::string(c.transport) == "rtu";
  const std::string model = exampleFile("vmc-xyfz-21.json");
  json sim = simConfig(model);
  sim["position_semantics"] = c.semantics;
  // The example raster runs at 6000 mm/min (>= 2 m/min asked for).
  ASSERT_GE(sim["path"]["feed_mm_min"].get<double>(), 2000.0);
  const Listening at =
      startSim(sim, rtu ? std::vector<std::string>{"--rtu", "--duration", "60"}
                        : std::vector<std::string>{"--port", "0", "--duration", "60"});
  ASSERT_EQ(at.kind, c.transport);
  json daemon =
      daemonConfig(at, model, rtu ? "volcompd-modbus-rtu.json" : "volcompd-modbus-tcp.json");
  daemon["position_semantics"] = c.semantics;
  const double periodS = daemon["cycle_period_ms"].get<double>() / 1000.0;
  startDaemon(daemon);

  // Two snapshots of the cumulative statistics split the run into an early and a late part.
  json early;
  ASSERT_TRUE(waitForSim(
      [&](const json& s) {
        early = s;
        return s["samples"].get<int>() > 500;
      },
      20s))
      << daemonLog();
  // The run ends after a number of samples, not of seconds: a loaded machine (or a sanitizer
  // build) samples less often than every tick.
  ASSERT_TRUE(waitForSim([&](const json& s) { return s["samples"].get<int>() > 1600; }, 50s))
      << daemonLog();
  const json report = finishSim();
  ASSERT_TRUE(report.is_object()) << daemonLog();
  stopDaemon();

  EXPECT_EQ(report["position_semantics"], c.semantics);
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  EXPECT_EQ(report["sessions"], 1);
  ASSERT_GT(report["samples"].get<int>(), 1500);
  const double un = report["rms_uncompensated_um"].get<double>();
  const double comp = report["rms_compensated_um"].get<double>();
  EXPECT_GT(un, 5.0) << "the example error is ~12 um RMS on this path";
  EXPECT_LE(comp, 0.05 * un) << report.dump();
  for (const char* axis : {"X", "Y", "Z"}) {
    const json& a = report["axes"][axis];
    EXPECT_LE(a["rms_compensated_um"].get<double>(), 0.05 * a["rms_uncompensated_um"].get<double>())
        << axis << ": " << a.dump();
  }

  // No drift: the late part's compensated RMS is not larger than the early part's beyond noise
  // (a feedback loop through the position registers would make it grow with every cycle).
  const double earlyRms = early["rms_compensated_um"].get<double>();
  const double lateRms = rmsBetween(early, report);
  EXPECT_LE(lateRms, 1.5 * earlyRms + 0.1) << "early " << earlyRms << " um, late " << lateRms;

  const auto rows = record();
  ASSERT_GT(rows.size(), 100U);
  expectWritesWithinLimits(rows, 0.1, 0.5, periodS);
  // No oscillation, once ramped in (0.5 s after the first write): the offsets follow the smooth
  // model along the path, so (a) the limiter is almost never active (an oscillation would hit
  // the rate limit every cycle), (b) the second difference of the offsets stays under 1 um
  // except at the few direction reversals, and (c) they stay within the size of the error
  // (< 15 um on this path, so 30 um is far from it and far from max_offset).
  std::size_t steady = 0, limited = 0, kinks = 0;
  for (std::size_t i = 2; i < rows.size(); ++i) {
    if (rows[i].tS < rows.front().tS + 0.5) continue;
    ++steady;
    if (rows[i].status & kLimited) ++limited;
    EXPECT_EQ(rows[i].status & (kActive | kFault | kDisabled), kActive) << "t=" << rows[i].tS;
    EXPECT_LT(largestAbs(rows[i].offsetMm), 0.030) << "t=" << rows[i].tS;
    for (std::size_t k = 0; k < 3; ++k) {
      const double d2 = rows[i].offsetMm[k] - 2 * rows[i - 1].offsetMm[k] + rows[i - 2].offsetMm[k];
      if (std::abs(d2) > 0.001) {
        ++kinks;
        break;
      }
    }
  }
  ASSERT_GT(steady, 50U);
  EXPECT_LE(limited, steady / 50) << limited << " limited of " << steady;
  EXPECT_LE(kinks, steady / 50) << kinks << " kinks of " << steady;
}

INSTANTIATE_TEST_SUITE_P(Wire, Compensation,
                         ::testing::Values(Case{"tcp", "commanded"}, Case{"tcp", "actual"},
                                           Case{"rtu", "commanded"}, Case{"rtu", "actual"}),
                         [](const ::testing::TestParamInfo<Case>& param) {
                           return std::string(param.param.transport) + "_" + param.param.semantics;
                         });

}  // namespace
}  // namespace volcomp::e2e
