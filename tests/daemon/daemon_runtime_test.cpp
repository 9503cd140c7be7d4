// The daemon around the loop: sd_notify against a real NOTIFY_SOCKET, readiness, watchdog pings
// from the cycle, status lines, stop with ramp-out, and reloads (good and rejected). The daemon
// runs in simulated time (SimulatedClock): the io_context runs on the test thread in short slices
// until a condition holds or a timeout expires, and no cycle waits for real.
#include "volcomp/daemon/daemon.hpp"

#include <gtest/gtest.h>

#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "daemon_fixture.hpp"
#include "fakes.hpp"
#include "notify_listener.hpp"
#include "simulated_clock.hpp"
#include "temp_files.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::daemon::testing {
namespace {

using namespace std::chrono_literals;
using loop::LoopState;
using loop::OffsetCommand;
using loop::testing::FakeModel;
using loop::testing::FakePort;
namespace status = loop::status;

TEST_F(DaemonTest, ReadyAfterTheFirstGoodCycleAndWatchdogFromTheCycle) {
  notifier.watchdog = 40ms;  // pings every 10 ms
  make();
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return notifier.count("WATCHDOG=1") >= 3; }));
  ASSERT_GE(notifier.count("READY=1"), 1);
  EXPECT_EQ(notifier.messages.front(), "READY=1");
  EXPECT_TRUE(daemon->ready());
}

TEST_F(DaemonTest, NoReadyWhileTheLinkIsDown) {
  port.connectError = std::make_error_code(std::errc::connection_refused);
  make();
  daemon->start();
  runUntil(io, [&] { return daemon->scheduler().cycles() >= 50; });
  EXPECT_EQ(notifier.count("READY=1"), 0);
  EXPECT_EQ(daemon->loop().state(), LoopState::LinkLost);
}

TEST_F(DaemonTest, StatusLineAtMostOncePerSecond) {
  make();
  daemon->start();
  ASSERT_TRUE(runUntil(
      io, [&] { return notifier.count("STATUS=") >= 1; }, 5s));
  const auto first = clock.now();
  ASSERT_TRUE(runUntil(
      io, [&] { return notifier.count("STATUS=") >= 2; }, 5s));
  EXPECT_GE(clock.now() - first, 900ms);
  std::string status;
  for (const auto& m : notifier.messages) {
    if (m.rfind("STATUS=", 0) == 0) status = m;
  }
  EXPECT_NE(status.find("active"), std::string::npos) << status;
  EXPECT_NE(status.find("Hz"), std::string::npos) << status;
  EXPECT_NE(status.find("offsets"), std::string::npos) << status;
  EXPECT_NE(status.find("fault none"), std::string::npos) << status;
}

TEST_F(DaemonTest, StopRampsOutWritesZeroInactiveAndFinishes) {
  make();
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.03; }));
  daemon->requestStop();
  ASSERT_TRUE(runUntil(io, [&] { return finished; }));
  EXPECT_EQ(notifier.count("STOPPING=1"), 1);
  EXPECT_EQ(port.last.status, 0);
  for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);
  EXPECT_EQ(daemon->loop().state(), LoopState::Finished);
}

TEST_F(DaemonTest, RejectedReloadKeepsTheModelAndReportsIt) {
  make([]() -> LoadedConfiguration {
    throw config::ConfigError("model.json", "components.EXX.values[3]", "expected a number");
  });
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return daemon->ready(); }));
  daemon->requestReload();
  EXPECT_EQ(notifier.count("RELOADING=1"), 1);
  ASSERT_TRUE(runUntil(io, [&] { return !daemon->reloading(); }));
  ASSERT_TRUE(runUntil(io, [&] { return (port.last.status & status::kReloadFailed) != 0; }));
  EXPECT_NE(daemon->reloadError().find("components.EXX.values[3]"), std::string::npos);
  EXPECT_EQ(&daemon->loop().model(), model.get());
  EXPECT_NE(daemon->statusLine().find("reload failed"), std::string::npos);
  EXPECT_EQ(notifier.messages.back(), "READY=1");  // RELOADING=1 is closed by READY=1
}

TEST_F(DaemonTest, GoodReloadSlewsToTheNewModel) {
  auto next = std::make_shared<FakeModel>(std::array<double, 3>{0.01, -0.02, 0.2});
  make([next] { return LoadedConfiguration{testConfig(), next, {}}; });
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.03; }));
  std::vector<OffsetCommand> writes;
  writes.reserve(100000);
  port.history = &writes;
  daemon->requestReload();
  ASSERT_TRUE(runUntil(io, [&] { return !daemon->reloading(); }));
  EXPECT_EQ(&daemon->loop().model(), next.get());
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.2; }));
  port.history = nullptr;
  bool sawReloadedBit = false;
  double previous = writes.front().offsetMm[2];
  for (const OffsetCommand& w : writes) {
    // Each write moves by at most 5 mm/s * 2 ms = 0.01 mm: the new model slews in.
    EXPECT_LE(w.offsetMm[2] - previous, 0.01 + 1e-12);
    previous = w.offsetMm[2];
    sawReloadedBit = sawReloadedBit || (w.status & status::kModelReloaded) != 0;
  }
  EXPECT_GE(writes.size(), 17u);  // (0.2 - 0.03) / 0.01
  EXPECT_TRUE(sawReloadedBit);
  EXPECT_TRUE(daemon->reloadError().empty());
}

/// A loader that blocks (as reading a FIFO or a hung mount does) until released, then fails.
struct BlockingLoad {
  std::mutex mutex;
  std::condition_variable cv;
  bool released = false;
  bool returned = false;
  int calls = 0;
  void release() {
    std::unique_lock lock(mutex);
    released = true;
    cv.notify_all();
    cv.wait_for(lock, 10s, [&] { return returned; });  // the helper thread is done with us
  }
};

Daemon::Loader blockingFirstLoad(const std::shared_ptr<BlockingLoad>& block) {
  return [block]() -> LoadedConfiguration {
    std::unique_lock lock(block->mutex);
    if (block->calls++ == 0) {
      block->cv.wait(lock, [&] { return block->released; });
      block->returned = true;
      block->cv.notify_all();
      throw config::ConfigError("model.fifo", "", "released at the end of the test");
    }
    return LoadedConfiguration{testConfig(), std::make_shared<FakeModel>(), {}};
  };
}

// A reload blocked on file I/O must not hold the stop: the offsets ramp out and the daemon
// finishes while the load still hangs.
TEST_F(DaemonTest, StopRampsOutAndFinishesWhileAReloadHangs) {
  auto block = std::make_shared<BlockingLoad>();
  make(blockingFirstLoad(block));
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return port.applied[2] == 0.03; }));
  daemon->requestReload();
  ASSERT_TRUE(runUntil(io, [&] { return daemon->scheduler().cycles() > 100; }));
  EXPECT_TRUE(daemon->reloading());
  daemon->requestStop();
  ASSERT_TRUE(runUntil(io, [&] { return finished; }));
  EXPECT_EQ(port.last.status, 0);
  for (double o : port.last.offsetMm) EXPECT_EQ(o, 0.0);
  daemon.reset();  // with the load still hanging
  block->release();
}

// A reload that hangs is given up after its timeout (real time; 0.3 s here instead of
// Daemon::kReloadTimeout): RELOAD_FAILED, the running model
// stays, and the next reload (SIGHUP) works. A SIGHUP during the hang follows it.
TEST_F(DaemonTest, HungReloadIsAbandonedAndTheNextOneWorks) {
  auto block = std::make_shared<BlockingLoad>();
  make(blockingFirstLoad(block));
  daemon->start();
  ASSERT_TRUE(runUntil(io, [&] { return daemon->ready(); }));
  daemon->setReloadTimeout(300ms);
  const auto start = std::chrono::steady_clock::now();
  daemon->requestReload();
  daemon->requestReload();  // remembered: runs once the first one ends
  ASSERT_TRUE(runUntil(io, [&] { return !daemon->reloadError().empty(); }));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 300ms);
  EXPECT_NE(daemon->reloadError().find("abandoned"), std::string::npos) << daemon->reloadError();
  EXPECT_EQ(&daemon->loop().model(), model.get());
  ASSERT_TRUE(runUntil(io, [&] { return (port.last.status & status::kReloadFailed) != 0; }));
  // The remembered reload runs and succeeds.
  ASSERT_TRUE(runUntil(io, [&] { return &daemon->loop().model() != model.get(); }));
  EXPECT_TRUE(daemon->reloadError().empty());
  EXPECT_FALSE(daemon->reloading());
  block->release();
}

// The real sd_notify path: libsystemd writes to the NOTIFY_SOCKET this fixture binds and
// announces in the environment.
class SystemdNotifierTest : public ::testing::Test {
 protected:
  SystemdNotifierTest() { ::setenv("NOTIFY_SOCKET", socket.path().c_str(), 1); }
  ~SystemdNotifierTest() override { ::unsetenv("NOTIFY_SOCKET"); }

  volcomp::testing::TempDir dir;
  testutil::NotifyListener socket{(dir.path() / "notify.sock").string()};
};

TEST_F(SystemdNotifierTest, SendsMessagesToTheNotifySocket) {
  SystemdNotifier notifier;
  notifier.notify("READY=1");
  EXPECT_EQ(socket.receive(5s).value_or("<nothing>"), "READY=1");
  notifier.notify("STATUS=active 100.0 Hz");
  EXPECT_EQ(socket.receive(5s).value_or("<nothing>"), "STATUS=active 100.0 Hz");
}

TEST(SystemdNotifier, WatchdogIntervalComesFromTheEnvironment) {
  SystemdNotifier notifier;
  ::unsetenv("WATCHDOG_USEC");
  ::unsetenv("WATCHDOG_PID");
  EXPECT_FALSE(notifier.watchdogInterval().has_value());
  ::setenv("WATCHDOG_USEC", "2000000", 1);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
  ASSERT_TRUE(notifier.watchdogInterval().has_value());
  EXPECT_EQ(*notifier.watchdogInterval(), std::chrono::seconds(2));
  ::unsetenv("WATCHDOG_USEC");
  ::unsetenv("WATCHDOG_PID");
}

// Without NOTIFY_SOCKET (not started by systemd) a message goes nowhere: the listener, announced
// again afterwards, gets the next message first (datagrams on a unix socket keep their order).
TEST_F(SystemdNotifierTest, WithoutNotifySocketNothingIsSent) {
  SystemdNotifier notifier;
  ::unsetenv("NOTIFY_SOCKET");
  notifier.notify("READY=1");
  ::setenv("NOTIFY_SOCKET", socket.path().c_str(), 1);
  notifier.notify("STATUS=announced");
  EXPECT_EQ(socket.receive(5s).value_or("<nothing>"), "STATUS=announced");
}

TEST_F(SystemdNotifierTest, DaemonLifecycleOverARealNotifySocket) {
  ::setenv("WATCHDOG_USEC", "40000", 1);
  ::setenv("WATCHDOG_PID", std::to_string(::getpid()).c_str(), 1);
  asio::io_context io;
  FakePort port;
  SimulatedClock clock(io);
  SystemdNotifier notifier;
  bool finished = false;
  Daemon daemon(
      io, port, clock, notifier,
      LoadedConfiguration{testConfig(), std::make_shared<FakeModel>(), {}},
      [] {
        return LoadedConfiguration{testConfig(), std::make_shared<FakeModel>(), {}};
      },
      [&] { finished = true; });
  daemon.start();

  std::vector<std::string> received;
  const auto receivedOne = [&](std::string_view prefix) {
    return runUntil(io, [&] {
      while (auto m = socket.receive(0ms)) received.push_back(*m);
      for (const auto& m : received) {
        if (m.rfind(prefix, 0) == 0) return true;
      }
      return false;
    });
  };
  EXPECT_TRUE(receivedOne("READY=1"));
  EXPECT_TRUE(receivedOne("WATCHDOG=1"));
  EXPECT_TRUE(receivedOne("STATUS=active"));
  daemon.requestReload();
  EXPECT_TRUE(receivedOne("RELOADING=1"));
  daemon.requestStop();
  EXPECT_TRUE(receivedOne("STOPPING=1"));
  EXPECT_TRUE(runUntil(io, [&] { return finished; }));
  ::unsetenv("WATCHDOG_USEC");
  ::unsetenv("WATCHDOG_PID");
}

}  // namespace
}  // namespace volcomp::daemon::testing
