#pragma once
// A Daemon around the loop's fakes in simulated time (SimulatedClock), with a notifier that
// records every message: the io_context runs on the test thread in short slices until a
// condition holds or a timeout expires, and no cycle waits for real.

#include <gtest/gtest.h>

#include <asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fakes.hpp"
#include "simulated_clock.hpp"
#include "volcomp/daemon/daemon.hpp"

namespace volcomp::daemon::testing {

using namespace std::chrono_literals;
using loop::testing::FakeModel;
using loop::testing::FakePort;

class RecordingNotifier final : public Notifier {
 public:
  void notify(std::string_view message) noexcept override { messages.emplace_back(message); }
  std::optional<std::chrono::microseconds> watchdogInterval() const noexcept override {
    return watchdog;
  }
  int count(std::string_view prefix) const {
    int n = 0;
    for (const auto& m : messages) n += m.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }
  std::vector<std::string> messages;
  std::optional<std::chrono::microseconds> watchdog;
};

inline config::DaemonConfig testConfig() {
  config::DaemonConfig c;
  c.file = "test.json";
  c.cyclePeriodMs = 2.0;
  c.limiter = loop::LimiterSettings::uniform(0.5, 5.0);  // 0.01 mm per 2 ms cycle
  c.staleTimeoutMs = 100.0;
  c.modelPath = "model.json";
  return c;
}

// Runs `io` one handler at a time until `done()` holds after one, or the real-time timeout;
// returns done(). One at a time, because in simulated time the daemon cycles as fast as the CPU
// runs it: a condition is seen as soon as it holds, and a listener drained in `done()` never
// falls behind the daemon's sd_notify datagrams.
inline bool runUntil(asio::io_context& io, const std::function<bool()>& done,
                     std::chrono::milliseconds timeout = 10s) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (!done() && std::chrono::steady_clock::now() < until) {
    io.restart();
    io.run_one_for(2ms);
  }
  return done();
}

class DaemonTest : public ::testing::Test {
 protected:
  void make(Daemon::Loader loader = {}) {
    if (!loader)
      loader = [] { return LoadedConfiguration{testConfig(), std::make_shared<FakeModel>(), {}}; };
    daemon = std::make_unique<Daemon>(io, port, clock, notifier,
                                      LoadedConfiguration{testConfig(), model, {}}, loader,
                                      [this] { finished = true; });
  }

  asio::io_context io;
  FakePort port;
  SimulatedClock clock{io};
  RecordingNotifier notifier;
  std::shared_ptr<FakeModel> model = std::make_shared<FakeModel>();
  std::unique_ptr<Daemon> daemon;
  bool finished = false;
};

}  // namespace volcomp::daemon::testing
