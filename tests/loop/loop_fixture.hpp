#pragma once
// A CompensationLoop wired to fakes, one cycle per call with the fake clock advanced by the period.

#include <gtest/gtest.h>

#include <chrono>
#include <memory>

#include "fakes.hpp"
#include "volcomp/loop/compensation_loop.hpp"

namespace volcomp::loop::testing {

inline LoopSettings testSettings() {
  LoopSettings s;
  s.period = std::chrono::milliseconds(10);
  s.limiter = LimiterSettings::uniform(0.5, 1.0);  // 0.01 mm per 10 ms cycle
  s.staleTimeout = std::chrono::milliseconds(100);
  s.travelMarginMm = 1.0;
  s.directionHysteresisMm = 0.002;
  s.reconnectInitial = std::chrono::milliseconds(100);
  s.reconnectMax = std::chrono::seconds(2);
  return s;
}

class LoopTest : public ::testing::Test {
 protected:
  void make() { loop = std::make_unique<CompensationLoop>(port, clock, model, settings); }
  CycleReport cycle() {
    clock.advance(settings.period);
    return loop->step();
  }
  /// Runs cycles until the written offsets equal the model's (or `limit` cycles).
  void runUntilSettled(int limit = 200) {
    for (int i = 0; i < limit; ++i) {
      cycle();
      if (port.writes > 0 && !(port.last.status & status::kLimited)) return;
    }
  }

  FakeClock clock;
  FakePort port;
  std::shared_ptr<FakeModel> model = std::make_shared<FakeModel>();
  LoopSettings settings = testSettings();
  std::unique_ptr<CompensationLoop> loop;
};

}  // namespace volcomp::loop::testing
