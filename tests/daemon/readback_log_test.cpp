// The log of a read-back outside +-max_offset, in simulated time: the values that caused the
// fault once, the return into the band once, and no fault line with the values of a later cycle,
// while the latched fault is logged again around failed writes (a fault of their own).
#include <gtest/gtest.h>

#include <string>
#include <system_error>

#include "daemon_fixture.hpp"
#include "log_capture.hpp"

namespace volcomp::daemon::testing {
namespace {

TEST_F(DaemonTest, AReadBackOutsideTheBandIsLoggedOnceWithItsValuesAndItsEndOnce) {
  LogCapture log;
  make();
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.03; }));
  const auto good = port.applied;
  port.holdApplied = true;
  port.applied = {0.7, -0.02, 0.03};  // a garbled reply: the band is 0.5 mm
  const auto outsideFrom = daemon->scheduler().cycles();
  ASSERT_TRUE(runUntil(io, [&] { return daemon->scheduler().cycles() > outsideFrom + 50; }));
  // Inside again; every fifth write then times out (a fault of its own for a cycle), so the
  // latched fault is logged again and again.
  int writeCalls = 0;
  port.duringWrite = [&] {
    port.writeError =
        ++writeCalls % 5 == 0 ? std::make_error_code(std::errc::timed_out) : std::error_code();
  };
  port.applied = good;
  port.holdApplied = false;
  ASSERT_TRUE(runUntil(io, [&] { return writeCalls > 100; }));
  port.duringWrite = nullptr;
  port.writeError = {};

  const auto values = log.lines("applied offsets read back");
  ASSERT_EQ(values.size(), 2u) << log.text();
  EXPECT_EQ(values[0].rfind("warning: applied offsets read back +0.7000 -0.0200 +0.0300 mm, "
                            "outside +-max_offset_mm (0.5 0.5 0.5 mm)",
                            0),
            0u)
      << values[0];
  EXPECT_EQ(values[1].rfind("info: applied offsets read back inside +-max_offset_mm again", 0), 0u)
      << values[1];
  EXPECT_NE(values[1].find("until the controller acknowledges it"), std::string::npos) << values[1];
  EXPECT_GT(log.lines("fault: readback-out-of-range").size(), 1u) << log.text();
  for (const std::string& line : log.lines("readback-out-of-range")) {
    EXPECT_EQ(line.find(" mm"), std::string::npos) << "values in a fault line: " << line;
  }
  for (const std::string& line : log.lines("")) EXPECT_LE(line.size(), 300u) << line;
}

}  // namespace
}  // namespace volcomp::daemon::testing
