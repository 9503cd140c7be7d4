#pragma once
// Fixture of the whole-process tests: volcomp-sim and volcompd started as processes in a private
// temporary directory, the simulator on a port (or pseudo-terminal) it chooses and announces in
// its LISTENING line, the daemon configured for it by a file written into that directory.
// Synchronisation is on conditions only: lines on the simulator's stdout (its LISTENING line,
// STATUS replies, the final report), the daemon's log file, sd_notify datagrams, process exit.
//
// The simulator's --record file is the wire-level truth: one row per write the controller
// received (t_s, offset_x_mm, offset_y_mm, offset_z_mm, status, heartbeat, partial, violation).

#include <stdlib.h>

#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "subprocess.hpp"
#include "temp_files.hpp"

namespace volcomp::e2e {

using namespace std::chrono_literals;
using nlohmann::json;
using testutil::Subprocess;

inline const std::string kSimPath = VOLCOMP_SIM_PATH;
inline const std::string kDaemonPath = VOLCOMPD_PATH;
inline const std::string kExamplesDir = VOLCOMP_EXAMPLES_DIR;

// Status word bits (daemon/include/volcomp/loop/status.hpp), as the controller sees them.
inline constexpr unsigned kActive = 1u << 0;
inline constexpr unsigned kDisabled = 1u << 1;
inline constexpr unsigned kFault = 1u << 2;
inline constexpr unsigned kLimited = 1u << 3;
inline constexpr unsigned kModelReloaded = 1u << 6;
inline constexpr unsigned kReloadFailed = 1u << 7;
inline constexpr unsigned kStopping = 1u << 8;
inline constexpr unsigned faultCodeOf(unsigned status) {
  return (status >> 12) & 0xFu;
}

/// One offset register count of the example register map (counts_per_mm 10000), mm.
inline constexpr double kQuantumMm = 1e-4;

/// One row of the simulator's --record file.
struct WriteRow {
  double tS = 0.0;
  std::array<double, 3> offsetMm{};
  unsigned status = 0;
  unsigned heartbeat = 0;
  bool partial = false;
  bool violation = false;
};

inline std::vector<WriteRow> readRecord(const std::filesystem::path& file) {
  std::vector<WriteRow> rows;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<double> f;
    std::stringstream fields(line);
    for (std::string s; std::getline(fields, s, ',');) f.push_back(std::stod(s));
    if (f.size() != 8) continue;
    rows.push_back({f[0],
                    {f[1], f[2], f[3]},
                    static_cast<unsigned>(f[4]),
                    static_cast<unsigned>(f[5]),
                    f[6] != 0.0,
                    f[7] != 0.0});
  }
  return rows;
}

inline double largestAbs(const std::array<double, 3>& v) {
  return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
}

/// Largest per-axis change between rows i-1 and i, mm.
inline double stepMm(const std::vector<WriteRow>& rows, std::size_t i) {
  double s = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    s = std::max(s, std::abs(rows[i].offsetMm[k] - rows[i - 1].offsetMm[k]));
  }
  return s;
}

/// Checks every recorded write against the limiter by itself (not trusting the simulator's
/// counter): |o| <= max_offset and |o_i - o_{i-1}| <= max_rate * period per write, each with
/// one register count of rounding (the codec rounds to the nearest count). The daemon's limiter
/// steps by max_rate * period per cycle whatever the wall-clock spacing of its writes, so the
/// bound is per consecutive write, including across an outage, unless the controller changed
/// the offsets itself in between: after a gap of more than `watchdogGapS` between two writes
/// the controller's heartbeat watchdog may have ramped them, the daemon follows its read-back,
/// and the step is judged against what the controller applied then, which only the simulator
/// knows (the row's violation flag, checked here for every write).
inline void expectWritesWithinLimits(
    const std::vector<WriteRow>& rows, double maxOffsetMm, double maxRateMmS, double periodS,
    double watchdogGapS = std::numeric_limits<double>::infinity()) {
  const double maxStep = maxRateMmS * periodS + kQuantumMm + 1e-9;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_LE(largestAbs(rows[i].offsetMm), maxOffsetMm + 0.5 * kQuantumMm + 1e-9)
        << "write " << i << " at t=" << rows[i].tS;
    ASSERT_FALSE(rows[i].partial) << "write " << i;
    ASSERT_FALSE(rows[i].violation) << "write " << i;
    if (i > 0 && rows[i].tS - rows[i - 1].tS <= watchdogGapS) {
      ASSERT_LE(stepMm(rows, i), maxStep) << "write " << i << " at t=" << rows[i].tS;
    }
  }
}

/// Where the simulator serves: "tcp" with a port, or "rtu" with a device.
struct Listening {
  std::string kind;
  int port = 0;
  std::string device;
};

class ProcessTest : public ::testing::Test {
 protected:
  void TearDown() override {
    daemon_.reset();
    sim_.reset();
  }

  static json example(const std::string& name) {
    std::ifstream in(kExamplesDir + "/" + name);
    return json::parse(in);
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// volcompd --probe [extra...] with `daemon` (written as volcompd.json); returns its exit
  /// status, its output in `out`.
  int probe(const json& daemon, const std::vector<std::string>& extra, std::string& out) const {
    std::vector<std::string> argv{kDaemonPath, "--config", writeJson("volcompd.json", daemon),
                                  "--probe"};
    argv.insert(argv.end(), extra.begin(), extra.end());
    Subprocess child(argv, "", {"NOTIFY_SOCKET", "JOURNAL_STREAM"});
    const int status = child.waitExit(std::chrono::seconds(30));
    out = child.output();
    return status;
  }

  std::string writeJson(const std::string& name, const json& content) const {
    std::ofstream(dir_ / name) << content.dump(2);
    return path(name);
  }

  /// The example simulator configuration with `modelFile` as its TRUE model and statistics from
  /// `settleMs` after the first write (the daemon's first cycles ramp the offsets in).
  static json simConfig(const std::string& modelFile, int settleMs = 500) {
    json s = example("sim-vmc.json");
    s["model"] = modelFile;
    s["settle_ms"] = settleMs;
    return s;
  }

  /// The example daemon configuration with an absolute model path and the transport section of
  /// `exampleName` pointed at the simulator.
  static json daemonConfig(const Listening& at, const std::string& modelFile,
                           const std::string& exampleName = "volcompd-modbus-tcp.json") {
    json d = example(exampleName);
    d["model"] = modelFile;
    if (at.kind == "tcp") {
      d["transport"]["port"] = at.port;
    } else {
      d["transport"]["device"] = at.device;
    }
    return d;
  }

  /// Starts a simulator (its record in `record`), waits for its LISTENING line.
  std::unique_ptr<Subprocess> spawnSim(const json& config, const std::vector<std::string>& args,
                                       const std::string& tag, Listening& at) {
    std::vector<std::string> argv{kSimPath, "--config", writeJson(tag + ".json", config),
                                  "--record", path(tag + "-writes.csv")};
    argv.insert(argv.end(), args.begin(), args.end());
    auto sim = std::make_unique<Subprocess>(argv, path(tag + ".err"));
    const auto line = sim->readLine(10s);
    if (!line) {
      ADD_FAILURE() << "no LISTENING line from the simulator: " << sim->stderrText();
      return sim;
    }
    std::istringstream words(*line);
    std::string listening, kind;
    words >> listening >> kind;
    EXPECT_EQ(listening, "LISTENING") << *line;
    at.kind = kind;
    if (kind == "tcp") {
      std::string host;
      words >> host >> at.port;
    } else {
      words >> at.device;
    }
    return sim;
  }

  /// The usual simulator of a test: `sim_`, recording to sim-writes.csv.
  Listening startSim(const json& config, const std::vector<std::string>& args) {
    Listening at;
    sim_ = spawnSim(config, args, "sim", at);
    return at;
  }

  void startDaemon(const json& config, const std::vector<std::string>& env = {},
                   bool setWatchdogPid = false) {
    const std::string configFile = writeJson("volcompd.json", config);
    std::vector<std::string> argv{kDaemonPath, "--config", configFile};
    if (setWatchdogPid) {
      // systemd sets WATCHDOG_PID to the service's own pid: a shell learns its pid ($$) and
      // execs the daemon, which keeps it.
      argv = {"/bin/sh",   "-c",       "WATCHDOG_PID=$$; export WATCHDOG_PID; exec \"$0\" \"$@\"",
              kDaemonPath, "--config", configFile};
    }
    daemon_ = std::make_unique<Subprocess>(argv, path("volcompd.err"), env);
  }

  std::string daemonLog() const { return daemon_ ? daemon_->stderrText() : std::string(); }

  /// The simulator's report so far (the "status" command on its stdin).
  static json statusOf(Subprocess& sim) {
    sim.writeLine("status");
    const auto line =
        sim.readLineMatching([](const std::string& l) { return l.rfind("STATUS ", 0) == 0; }, 10s);
    if (!line) return {};
    return json::parse(line->substr(7));
  }
  json simStatus() { return statusOf(*sim_); }

  /// Asks the simulator for its status until `condition(status)` holds.
  template <typename Condition>
  bool waitForSim(Condition&& condition, std::chrono::milliseconds timeout) {
    return testutil::waitUntil(
        [&] {
          const json s = simStatus();
          return s.is_object() && condition(s);
        },
        timeout);
  }

  /// Waits until the offsets the controller applies reach `mm` on some axis.
  bool waitForAppliedOffset(double mm, std::chrono::milliseconds timeout = 20s) {
    return waitForSim(
        [&](const json& s) {
          double largest = 0.0;
          for (double o : s["applied_offset_mm"]) largest = std::max(largest, std::abs(o));
          return largest >= mm;
        },
        timeout);
  }

  /// Waits until `sim` has received `more` writes beyond those it reports now.
  static bool waitForMoreWrites(Subprocess& sim, int more,
                                std::chrono::milliseconds timeout = 15s) {
    int base = -1;
    return testutil::waitUntil(
        [&] {
          const json s = statusOf(sim);
          if (!s.is_object()) return false;
          const int writes = s["writes"].get<int>();
          if (base < 0) base = writes;
          return writes >= base + more;
        },
        timeout);
  }

  /// Ends a simulator ("quit" on stdin, or it ends by --duration) and returns its final report.
  static json finish(Subprocess& sim, bool sendQuit = true) {
    if (sendQuit) sim.writeLine("quit");
    const auto line =
        sim.readLineMatching([](const std::string& l) { return !l.empty() && l[0] == '{'; }, 30s);
    EXPECT_EQ(sim.waitExit(10s), 0);
    if (!line) return {};
    return json::parse(*line);
  }
  json finishSim(bool sendQuit = true) { return finish(*sim_, sendQuit); }

  /// SIGTERM to the daemon; expects a clean exit 0 within the unit's stop timeout.
  void stopDaemon() {
    ASSERT_TRUE(daemon_);
    daemon_->signal(SIGTERM);
    EXPECT_EQ(daemon_->waitExit(10s), 0) << daemonLog();
  }

  std::vector<WriteRow> record(const std::string& tag = "sim") const {
    return readRecord(dir_ / (tag + "-writes.csv"));
  }

  // Declared before the processes that write into it, so that it goes after them. Kept for
  // inspection when the test failed.
  volcomp::testing::TempDir tmp_;
  const std::filesystem::path dir_ = tmp_.path();
  std::unique_ptr<Subprocess> sim_;
  std::unique_ptr<Subprocess> daemon_;
};

/// Example file path.
inline std::string exampleFile(const std::string& name) {
  return kExamplesDir + "/" + name;
}

/// The model of `source` with every error value (tables, polynomials, constants) multiplied by
/// `factor`: the same shape of error, `factor` times larger.
inline json scaledModel(const json& source, double factor) {
  json m = source;
  for (auto& [name, component] : m["components"].items()) {
    if (component.is_number()) {
      component = component.get<double>() * factor;
      continue;
    }
    for (const char* key : {"values", "values_negative", "polynomial"}) {
      if (!component.contains(key)) continue;
      for (auto& v : component[key]) v = v.get<double>() * factor;
    }
  }
  return m;
}

}  // namespace volcomp::e2e
