// A reload's limiter against the running one: the log lines (old -> new per axis, the widened
// ones with what to do, every line short), and the daemon in simulated time across reloads that
// widen (not taken, every write within the running limits), widen again (compared against what
// runs, not against the file before) and tighten (taken at once).
#include "volcomp/daemon/limit_changes.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "daemon_fixture.hpp"
#include "log_capture.hpp"

namespace volcomp::daemon::testing {
namespace {

using loop::AxisLimits;
using loop::LimiterSettings;
using loop::OffsetCommand;

constexpr std::size_t kLongestLine = 300;

TEST(LimitChanges, AWideningReloadIsOneWarningPerLimitWithOldNewAndWhatToDo) {
  const LimitChangeLines lines = describeLimitChanges(
      LimiterSettings::uniform(0.1, 0.5), LimiterSettings::uniform(2.0, 1000.0), "volcompd.json");
  EXPECT_TRUE(lines.tightened.empty());
  ASSERT_EQ(lines.widened.size(), 2u);
  EXPECT_NE(
      lines.widened[0].find("limiter.max_offset_mm of volcompd.json widens X/Y/Z 0.1 -> 2 mm"),
      std::string::npos)
      << lines.widened[0];
  EXPECT_NE(lines.widened[1].find("limiter.max_rate_mm_s of volcompd.json widens X/Y/Z 0.5 -> "
                                  "1000 mm/s"),
            std::string::npos)
      << lines.widened[1];
  for (const std::string& line : lines.widened) {
    EXPECT_NE(line.find("not taken"), std::string::npos) << line;
    EXPECT_NE(line.find("systemctl restart volcompd"), std::string::npos) << line;
    EXPECT_LE(line.size(), kLongestLine) << line;
  }
}

TEST(LimitChanges, AxesWithDifferentChangesAreNamedOneByOne) {
  LimiterSettings running;
  running.axes = {AxisLimits{0.1, 0.5, 0.0}, AxisLimits{0.1, 0.5, 0.0}, AxisLimits{0.05, 0.5, 0.0}};
  LimiterSettings requested;
  requested.axes = {AxisLimits{0.05, 0.5, 0.0}, AxisLimits{0.2, 0.5, 0.0},
                    AxisLimits{0.03, 0.5, 0.0}};
  const LimitChangeLines lines = describeLimitChanges(running, requested, "m.json");
  ASSERT_EQ(lines.tightened.size(), 1u);
  EXPECT_EQ(lines.tightened[0],
            "limiter.max_offset_mm tightened by the reload: X 0.1 -> 0.05 mm, Z 0.05 -> 0.03 mm, "
            "taken now");
  ASSERT_EQ(lines.widened.size(), 1u);
  EXPECT_NE(lines.widened[0].find("widens Y 0.1 -> 0.2 mm:"), std::string::npos)
      << lines.widened[0];
}

TEST(LimitChanges, AnAccelerationLimitOfZeroIsNone) {
  const LimitChangeLines added = describeLimitChanges(
      LimiterSettings::uniform(0.1, 0.5, 0.0), LimiterSettings::uniform(0.1, 0.5, 20.0), "f");
  ASSERT_EQ(added.tightened.size(), 1u);
  EXPECT_NE(added.tightened[0].find("max_accel_mm_s2 tightened by the reload: X/Y/Z none -> 20 "
                                    "mm/s^2"),
            std::string::npos)
      << added.tightened[0];
  const LimitChangeLines removed = describeLimitChanges(
      LimiterSettings::uniform(0.1, 0.5, 20.0), LimiterSettings::uniform(0.1, 0.5, 0.0), "f");
  ASSERT_EQ(removed.widened.size(), 1u);
  EXPECT_NE(removed.widened[0].find("widens X/Y/Z 20 mm/s^2 -> none:"), std::string::npos)
      << removed.widened[0];
}

TEST(LimitChanges, TheSameLimitsSayNothing) {
  const LimitChangeLines lines = describeLimitChanges(LimiterSettings::uniform(0.1, 0.5, 3.0),
                                                      LimiterSettings::uniform(0.1, 0.5, 3.0), "f");
  EXPECT_TRUE(lines.tightened.empty());
  EXPECT_TRUE(lines.widened.empty());
}

/// A loader that hands out the configurations of `limiters` in turn, with a model asking for
/// `offsetMm`.
Daemon::Loader reloadsWith(std::vector<LimiterSettings> limiters, std::array<double, 3> offsetMm) {
  auto next = std::make_shared<std::size_t>(0);
  return [limiters = std::move(limiters), offsetMm, next] {
    config::DaemonConfig c = testConfig();
    c.limiter = limiters.at(std::min(*next, limiters.size() - 1));
    ++*next;
    return LoadedConfiguration{c, std::make_shared<FakeModel>(offsetMm), {}};
  };
}

class ReloadLimits : public DaemonTest {
 protected:
  void reload() {
    daemon->requestReload();
    ASSERT_TRUE(runUntil(io, [&] { return !daemon->reloading(); }));
  }
  LogCapture log;
};

// Running 0.5 mm, 5 mm/s (0.01 mm per 2 ms cycle); the file widens to 2 mm, 1000 mm/s with a
// model asking for 0.9 mm: every write stays within the running limits, and a warning per limit
// says old and new and to restart.
TEST_F(ReloadLimits, AWideningReloadKeepsTheRunningLimitsForEveryWrite) {
  make(reloadsWith({LimiterSettings::uniform(2.0, 1000.0)}, {0.9, -0.9, 0.03}));
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.03; }));
  std::vector<OffsetCommand> writes;
  writes.reserve(100000);
  port.history = &writes;
  reload();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[0] == 0.5 && port.applied[1] == -0.5; }));
  port.history = nullptr;
  EXPECT_EQ(daemon->loop().settings().limiter, LimiterSettings::uniform(0.5, 5.0));
  ASSERT_FALSE(writes.empty());
  std::array<double, 3> previous = {0.01, -0.02, 0.03};
  for (const OffsetCommand& w : writes) {
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_LE(std::abs(w.offsetMm[k]), 0.5);
      EXPECT_LE(std::abs(w.offsetMm[k] - previous[k]), 0.01 + 1e-12);
    }
    previous = w.offsetMm;
  }
  const auto offset = log.lines("limiter.max_offset_mm of test.json widens X/Y/Z 0.5 -> 2 mm");
  const auto rate = log.lines("limiter.max_rate_mm_s of test.json widens X/Y/Z 5 -> 1000 mm/s");
  ASSERT_EQ(offset.size(), 1u) << log.text();
  ASSERT_EQ(rate.size(), 1u) << log.text();
  EXPECT_EQ(offset[0].rfind("warning: ", 0), 0u) << offset[0];
  EXPECT_NE(rate[0].find("systemctl restart volcompd"), std::string::npos) << rate[0];
}

// A later reload compares against what runs: after 0.5 -> 2 mm was not taken, 1 mm is still a
// widening of 0.5 mm; 0.3 mm and 2 mm/s are a tightening, taken at once and logged.
TEST_F(ReloadLimits, ALaterReloadComparesAgainstTheRunningLimits) {
  make(reloadsWith({LimiterSettings::uniform(2.0, 1000.0), LimiterSettings::uniform(1.0, 5.0),
                    LimiterSettings::uniform(0.3, 2.0)},
                   {0.01, -0.02, 0.03}));
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return daemon->ready(); }));
  reload();
  reload();
  EXPECT_EQ(log.lines("widens X/Y/Z 0.5 -> 1 mm").size(), 1u) << log.text();
  EXPECT_TRUE(log.lines("2 -> 1 mm").empty()) << log.text();
  EXPECT_EQ(daemon->loop().settings().limiter, LimiterSettings::uniform(0.5, 5.0));
  reload();
  EXPECT_EQ(daemon->loop().settings().limiter, LimiterSettings::uniform(0.3, 2.0));
  const auto offset = log.lines("limiter.max_offset_mm tightened by the reload: X/Y/Z 0.5 -> 0.3");
  const auto rate = log.lines("limiter.max_rate_mm_s tightened by the reload: X/Y/Z 5 -> 2 mm/s");
  ASSERT_EQ(offset.size(), 1u) << log.text();
  ASSERT_EQ(rate.size(), 1u) << log.text();
  EXPECT_EQ(offset[0].rfind("info: ", 0), 0u) << offset[0];
}

}  // namespace
}  // namespace volcomp::daemon::testing
