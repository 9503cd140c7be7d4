#pragma once
// The server-role process tests' fixture: volcompd as a process holding the example register bank
// on a port it chooses (read from its log line), the limiter checks of what a master reads, and
// the path the master's positions follow.

#include <algorithm>
#include <array>
#include <regex>
#include <string>
#include <vector>

#include "modbus_master.hpp"
#include "process_fixture.hpp"
#include "volcomp/daemon/configuration.hpp"
#include "wait_until.hpp"

namespace volcomp::e2e {

inline constexpr double kMaxOffsetMm = 0.1;  // the example's limiter
inline constexpr double kMaxRateMmS = 0.5;
inline constexpr double kPeriodS = 0.010;
inline constexpr std::uint16_t kEnabledHomed = 3;
inline constexpr std::array<double, 3> kFrom{100.0, 100.0, -400.0};
inline constexpr std::array<double, 3> kTo{300.0, 200.0, -300.0};

/// Every read: |o| <= max_offset. Between two reads of written outputs, the offsets moved by at
/// most max_rate times one period per cycle the daemon wrote in between (its heartbeat counts
/// them; the limiter's dt is capped at one period), plus a register count of rounding: the
/// daemon's own count of cycles, so the master's scheduling does not enter. Where the heartbeat
/// started again (a restarted daemon, which begins from the applied offsets the master reports),
/// the time between the reads plus one cycle bounds the step instead. A bank nothing has been
/// written to yet (heartbeat and status 0: a daemon just started) is not an output, so it is
/// not a base for the next step.
inline void expectReadsWithinLimits(const std::vector<MasterRead>& reads) {
  ASSERT_FALSE(reads.empty());
  constexpr unsigned kSameProcessCycles = 1000;  // a larger count: the heartbeat started again
  const MasterRead* previous = nullptr;
  for (std::size_t i = 0; i < reads.size(); ++i) {
    const MasterRead& r = reads[i];
    ASSERT_LE(largestAbs(r.offsetMm), kMaxOffsetMm + 0.5 * kQuantumMm + 1e-9) << i;
    if (r.heartbeat == 0 && r.status == 0) continue;
    if (previous != nullptr) {
      const auto cycles = static_cast<std::uint16_t>(r.heartbeat - previous->heartbeat);
      const double dt = r.tS - previous->tS;
      const double windowS = cycles < kSameProcessCycles ? cycles * kPeriodS : dt + kPeriodS;
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_LE(std::abs(r.offsetMm[k] - previous->offsetMm[k]),
                  kMaxRateMmS * windowS + kQuantumMm + 1e-9)
            << "read " << i << " axis " << k << " cycles " << cycles << " dt " << dt;
      }
    }
    previous = &r;
  }
}

/// Moves from kFrom to kTo in the positive direction on every axis over `moveCycles`, then holds.
inline std::array<double, 3> pathAt(int cycle, int moveCycles) {
  const double s = std::min(1.0, static_cast<double>(cycle) / moveCycles);
  std::array<double, 3> q{};
  for (std::size_t k = 0; k < 3; ++k) q[k] = kFrom[k] + s * (kTo[k] - kFrom[k]);
  return q;
}

class ModbusServerTest : public ProcessTest {
 protected:
  /// The example server configuration on a free port with the example model.
  static json serverConfig() {
    json d = example("volcompd-modbus-server-tcp.json");
    d["model"] = exampleFile("vmc-xyfz-21.json");
    d["transport"]["port"] = 0;
    return d;
  }

  /// Starts the daemon and returns the port from its "listening on" line.
  int startServer(const json& config) {
    startDaemon(config);
    static const std::regex line("listening on tcp 127\\.0\\.0\\.1:([0-9]+)");
    std::smatch m;
    std::string log;
    const bool found = testutil::waitUntil(
        [&] {
          log = daemonLog();
          return std::regex_search(log, m, line);
        },
        10s);
    if (!found) {
      ADD_FAILURE() << "no listening line: " << log;
      return 0;
    }
    return std::stoi(m[1].str());
  }

  /// The offsets the daemon's model asks for at `q`, reached moving in direction `d` on every
  /// axis (Unknown: held there since the daemon started; bidirectional tables then give the mean).
  std::array<double, 3> modelOffset(const std::array<double, 3>& q,
                                    model::Direction d = model::Direction::Positive) const {
    const auto loaded = daemon::loadConfiguration(path("volcompd.json"));
    return loaded.model->offset(q, {d, d, d}).offsetMm;
  }

  /// Runs `cycles` master cycles along the path (from cycle `first`), paced at 10 ms.
  static void run(Master& master, int first, int cycles, int moveCycles = 100,
                  std::uint16_t flags = kEnabledHomed) {
    Pacer pacer(10ms);
    for (int i = first; i < first + cycles; ++i) {
      pacer.tick();
      master.cycle(pathAt(i, moveCycles), flags);
    }
  }

  void expectOffsetsOfTheModel(const Master& master,
                               model::Direction d = model::Direction::Positive) {
    ASSERT_FALSE(master.reads.empty());
    const MasterRead& last = master.reads.back();
    EXPECT_EQ(last.status & (kActive | kFault), kActive) << last.status << "\n" << daemonLog();
    const auto expected = modelOffset(kTo, d);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(last.offsetMm[k], expected[k], 1.5 * kQuantumMm) << "axis " << k;
    }
    EXPECT_GT(largestAbs(expected), 10 * kQuantumMm);  // a real offset, not zero
  }
};

}  // namespace volcomp::e2e
