// End to end: volcompd compensating volcomp-sim's machine over Modbus TCP and RTU, both as
// processes started from the example configurations (config/examples/sim-vmc.json and
// volcompd-modbus-tcp.json). The simulator's report is the measurement: the true tool-tip error
// with and without compensation, and every write checked against the daemon's limiter settings.
//
// Expected sizes: the simulator's TRUE model (vmc-xyfz-21-true.json) is the daemon's model plus
// what a calibration missed: +6 % of the X lead error (<= 1.2 um), +2.5 urad of EC0Y (<= 1.1 um
// over Y 50..450), and a Z straightness ramp along Y (<= 1.5 um). On the example raster the
// uncompensated error is ~12 um RMS; the compensated one can therefore not go below ~1-3 um, and
// must stay well under half of the uncompensated one.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "subprocess.hpp"
#include "temp_files.hpp"
#include "wait_until.hpp"

namespace volcomp::test {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

const std::string kSim = VOLCOMP_SIM_PATH;
const std::string kDaemon = VOLCOMPD_PATH;
const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

class ModbusE2e : public ::testing::Test {
 protected:
  static json example(const std::string& name) {
    return json::parse(std::ifstream(kExamples + "/" + name));
  }

  std::string write(const std::string& name, const json& content) const {
    const auto file = dir_ / name;
    std::ofstream(file) << content.dump(2);
    return file.string();
  }

  /// Starts the simulator and returns the second and following words of its LISTENING line
  /// ("tcp 127.0.0.1 PORT" or "rtu DEVICE").
  std::vector<std::string> startSim(const json& simConfig, std::vector<std::string> args) {
    std::vector<std::string> argv{kSim, "--config", write("sim.json", simConfig), "--record",
                                  (dir_ / "writes.csv").string()};
    argv.insert(argv.end(), args.begin(), args.end());
    sim_ = std::make_unique<testutil::Subprocess>(argv, (dir_ / "sim.err").string());
    const auto line = sim_->readLine(10s);
    if (!line) return {};
    std::istringstream in(*line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    if (words.empty() || words[0] != "LISTENING") return {};
    words.erase(words.begin());
    return words;
  }

  void startDaemon(const json& daemonConfig) {
    daemon_ = std::make_unique<testutil::Subprocess>(
        std::vector<std::string>{kDaemon, "--config", write("volcompd.json", daemonConfig)},
        (dir_ / "volcompd.err").string());
  }

  /// The daemon configuration of the example, talking to the given transport.
  static json daemonConfig(const json& transport) {
    json d = example("volcompd-modbus-tcp.json");
    d["model"] = kExamples + "/vmc-xyfz-21.json";
    d["transport"] = transport;
    return d;
  }

  static json simConfig() {
    json s = example("sim-vmc.json");
    s["model"] = kExamples + "/vmc-xyfz-21-true.json";
    // Statistics from 0.5 s after the first write: the daemon's first cycles ramp in at max_rate.
    s["settle_ms"] = 500;
    return s;
  }

  /// Waits for the simulator's final report line (it ends by --duration).
  json simReport(std::chrono::milliseconds timeout = 30s) {
    for (;;) {
      const auto line = sim_->readLine(timeout);
      if (!line) return {};
      if (line->rfind("STATUS ", 0) == 0) continue;
      return json::parse(*line);
    }
  }

  /// The current report, asked for on stdin.
  json simStatus() {
    sim_->writeLine("status");
    const auto line = sim_->readLine(10s);
    if (!line || line->rfind("STATUS ", 0) != 0) return {};
    return json::parse(line->substr(7));
  }

  std::string daemonLog() const {
    std::ifstream in(dir_ / "volcompd.err");
    return {std::istreambuf_iterator<char>(in), {}};
  }

  /// Rows of the --record file: t, ox, oy, oz, status, heartbeat, partial, violation.
  std::vector<std::vector<double>> records() const {
    std::ifstream in(dir_ / "writes.csv");
    std::vector<std::vector<double>> rows;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      std::vector<double> row;
      std::stringstream fields(line);
      for (std::string f; std::getline(fields, f, ',');) row.push_back(std::stod(f));
      rows.push_back(row);
    }
    return rows;
  }

  void expectCompensatedWithinLimits(const json& report) const {
    ASSERT_TRUE(report.is_object()) << daemonLog();
    EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
    EXPECT_EQ(report["partial_writes"], 0);
    EXPECT_GT(report["samples"].get<int>(), 1000);
    const double un = report["rms_uncompensated_um"].get<double>();
    const double comp = report["rms_compensated_um"].get<double>();
    EXPECT_GT(un, 5.0);
    EXPECT_LT(comp, 0.4 * un) << report.dump();
  }

  // Declared before the processes that write into it, so that it goes after them.
  volcomp::testing::TempDir tmp_;
  const std::filesystem::path dir_ = tmp_.path();
  std::unique_ptr<testutil::Subprocess> sim_;
  std::unique_ptr<testutil::Subprocess> daemon_;
};

TEST_F(ModbusE2e, TcpCompensatesWithinTheLimitsAndStopsCleanly) {
  const auto where = startSim(simConfig(), {"--port", "0", "--duration", "4"});
  ASSERT_EQ(where.size(), 3U);
  json transport = example("volcompd-modbus-tcp.json")["transport"];
  transport["port"] = std::stoi(where[2]);
  startDaemon(daemonConfig(transport));
  const json report = simReport();
  expectCompensatedWithinLimits(report);
  EXPECT_EQ(report["sessions"], 1);
  EXPECT_EQ(sim_->waitExit(10s), 0);
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
}

TEST_F(ModbusE2e, StopRampsTheOffsetsOutAndWritesZeroAndInactive) {
  // A slow limiter (0.05 mm/s, 0.5 um per 10 ms cycle) so that ramping ~10 um out takes ~20
  // cycles, every one of them checked by the simulator.
  json sim = simConfig();
  sim["limits"]["max_rate_mm_s"] = 0.05;
  const auto where = startSim(sim, {"--port", "0"});
  ASSERT_EQ(where.size(), 3U);
  json transport = example("volcompd-modbus-tcp.json")["transport"];
  transport["port"] = std::stoi(where[2]);
  json d = daemonConfig(transport);
  d["limiter"]["max_rate_mm_s"] = 0.05;
  startDaemon(d);
  // Wait until an offset is well away from zero (> 5 um), so the ramp-out is visible.
  ASSERT_TRUE(testutil::waitUntil(
      [&] {
        const json s = simStatus();
        if (!s.is_object()) return false;
        double largest = 0;
        for (double o : s["applied_offset_mm"]) largest = std::max(largest, std::abs(o));
        return largest > 0.005;
      },
      20s))
      << daemonLog();
  const std::size_t writesBeforeStop = simStatus()["writes"].get<std::size_t>();
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  sim_->signal(SIGTERM);
  const json report = simReport();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  const auto rows = records();
  // 5 um or more at 0.5 um per cycle: at least 10 more writes during the ramp-out.
  ASSERT_GE(rows.size(), writesBeforeStop + 10);
  const auto& last = rows.back();
  EXPECT_EQ(last[1], 0.0);
  EXPECT_EQ(last[2], 0.0);
  EXPECT_EQ(last[3], 0.0);
  EXPECT_EQ(last[4], 0.0) << "status word 0 = inactive";
  for (double o : report["applied_offset_mm"]) EXPECT_EQ(o, 0.0);
}

TEST_F(ModbusE2e, LinkDropReconnectsAndContinuesWithoutAJump) {
  // The link is down from 1.5 s to 2.3 s; the controller keeps the applied offsets meanwhile
  // (no heartbeat watchdog here), so the first write after reconnecting must continue from them.
  json sim = simConfig();
  sim["heartbeat_timeout_ms"] = 0;
  const auto where =
      startSim(sim, {"--port", "0", "--duration", "5", "--event", "1.5:drop-link:0.8"});
  ASSERT_EQ(where.size(), 3U);
  json transport = example("volcompd-modbus-tcp.json")["transport"];
  transport["port"] = std::stoi(where[2]);
  startDaemon(daemonConfig(transport));
  const json report = simReport();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["sessions"], 2) << daemonLog();
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  // Writes continue after the outage (about 2.7 s of the run at 100 Hz).
  const auto rows = records();
  ASSERT_FALSE(rows.empty());
  EXPECT_GT(rows.back()[0], 4.0);
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
}

TEST_F(ModbusE2e, ExceptionRepliesAndAStalledControllerAreSurvivedWithinTheLimits) {
  // 1.5-2.0 s every request gets exception 4; 2.5-3.0 s the controller does not answer (three
  // 50 ms timeouts in a row: the driver reports link loss and the daemon reconnects).
  const auto where = startSim(simConfig(), {"--port", "0", "--duration", "5", "--event",
                                            "1.5:exception:4:0.5", "--event", "2.5:stall:0.5"});
  ASSERT_EQ(where.size(), 3U);
  json transport = example("volcompd-modbus-tcp.json")["transport"];
  transport["port"] = std::stoi(where[2]);
  startDaemon(daemonConfig(transport));
  const json report = simReport();
  ASSERT_TRUE(report.is_object());
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  EXPECT_GT(report["exceptions_sent"].get<int>(), 0);
  EXPECT_GT(report["requests_unanswered"].get<int>(), 0);
  const auto rows = records();
  ASSERT_FALSE(rows.empty());
  EXPECT_GT(rows.back()[0], 4.0) << "the daemon writes again after both faults";
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
}

TEST_F(ModbusE2e, ActualPositionSemanticsCompensateWithoutFeedback) {
  json sim = simConfig();
  sim["position_semantics"] = "actual";
  const auto where = startSim(sim, {"--port", "0", "--duration", "4"});
  ASSERT_EQ(where.size(), 3U);
  json transport = example("volcompd-modbus-tcp.json")["transport"];
  transport["port"] = std::stoi(where[2]);
  json d = daemonConfig(transport);
  d["position_semantics"] = "actual";
  startDaemon(d);
  expectCompensatedWithinLimits(simReport());
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
}

TEST_F(ModbusE2e, RtuOverAPseudoTerminal) {
  const auto where = startSim(simConfig(), {"--rtu", "--duration", "4"});
  ASSERT_EQ(where.size(), 2U);
  ASSERT_EQ(where[0], "rtu");
  json transport = example("volcompd-modbus-rtu.json")["transport"];
  transport["device"] = where[1];
  startDaemon(daemonConfig(transport));
  expectCompensatedWithinLimits(simReport());
  daemon_->signal(SIGTERM);
  EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
}

}  // namespace
}  // namespace volcomp::test
