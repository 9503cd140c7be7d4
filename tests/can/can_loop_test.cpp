// The whole loop over real SocketCAN: the daemon's CompensationLoop with the CAN driver on one
// side of vcan0, the simulated machine behind a CanSimNode on the other. The simulator's true
// error model is the daemon's model, so compensation must remove nearly all of the error; every
// write is checked by the simulator against the limiter settings.
#include <atomic>
#include <cstdlib>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <linux/can/error.h>
#include <asio/executor_work_guard.hpp>
#include <asio/post.hpp>
#include <asio/steady_timer.hpp>

#include "vcan_util.hpp"
#include "volcomp/can/controller_port.hpp"
#include "volcomp/config/can_config.hpp"
#include "volcomp/daemon/configuration.hpp"
#include "volcomp/loop/compensation_loop.hpp"
#include "volcomp/loop/steady_clock.hpp"
#include "volcomp/sim/can_sim_node.hpp"
#include "volcomp/sim/machine.hpp"
#include "volcomp/sim/sim_config.hpp"
#include "wait_until.hpp"

namespace volcomp::can {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

json sig(int id, int start, int length, const char* type, double scale) {
  return {{"id", id}, {"start_bit", start}, {"length", length}, {"type", type}, {"scale", scale}};
}

/// Inputs: 0x100 X, Y (int28, 0.1 µm) + counter; 0x101 Z (int32) + enable, homed + counter;
/// 0x102 applied offsets (int16, 0.1 µm) + counter. Outputs: 0x300 offsets (int16, 0.1 µm) +
/// status; 0x301 heartbeat.
json loopConfig(bool sync) {
  json c{{"interface", test::interfaceName()},
         {"trigger", sync ? "sync" : "broadcast"},
         {"timeouts", {{"stale_ms", 100}}},
         {"inputs",
          {{"position",
            {{"X", sig(0x100, 0, 28, "signed", 0.0001)},
             {"Y", sig(0x100, 28, 28, "signed", 0.0001)},
             {"Z", sig(0x101, 0, 32, "signed", 0.0001)}}},
           {"enable", sig(0x101, 32, 1, "unsigned", 1)},
           {"homed", sig(0x101, 33, 1, "unsigned", 1)},
           {"applied_offset",
            {{"X", sig(0x102, 0, 16, "signed", 0.0001)},
             {"Y", sig(0x102, 16, 16, "signed", 0.0001)},
             {"Z", sig(0x102, 32, 16, "signed", 0.0001)}}},
           {"sequence",
            json::array({sig(0x100, 56, 8, "unsigned", 1), sig(0x101, 56, 8, "unsigned", 1),
                         sig(0x102, 56, 8, "unsigned", 1)})}}},
         {"outputs",
          {{"offset",
            {{"X", sig(0x300, 0, 16, "signed", 0.0001)},
             {"Y", sig(0x300, 16, 16, "signed", 0.0001)},
             {"Z", sig(0x300, 32, 16, "signed", 0.0001)}}},
           {"status", sig(0x300, 48, 16, "unsigned", 1)},
           {"heartbeat", sig(0x301, 0, 8, "unsigned", 1)}}}};
  if (sync) {
    c["sync"] = {{"id", 0x80}};
    c["timeouts"]["response_ms"] = 15;  // below the 20 ms cycle of the sync case
  }
  return c;
}

std::string modelFile() {
  const char* dir = std::getenv("VOLCOMP_CAN_DATA");
  return std::string(dir && *dir ? dir : ".") + "/vmc-xyfz-21.json";
}

struct LoopCase {
  bool sync;
  loop::PositionSemantics semantics;
};

class CanWholeLoop : public ::testing::TestWithParam<LoopCase> {};

/// Stops the loop, stepping it at its period until it has finished, and waits until the
/// simulator has taken its last write (status 0) off the socket.
void stopAndWaitForTheLastWrite(loop::CompensationLoop& loop,
                                std::chrono::steady_clock::time_point& deadline,
                                std::chrono::nanoseconds period, const sim::Machine& machine) {
  loop.requestStop();
  for (int i = 0; i < 1000 && !loop.finished(); ++i) {
    loop.step();
    deadline += period;
    std::this_thread::sleep_until(deadline);  // the loop's own period
  }
  EXPECT_TRUE(loop.finished());
  EXPECT_TRUE(testutil::waitUntil([&] {
    const auto writes = machine.writes();
    return !writes.empty() && writes.back().status == 0;
  })) << "last status seen by the simulator: "
      << (machine.writes().empty() ? -1 : machine.writes().back().status);
}

TEST_P(CanWholeLoop, CompensatesTheSimulatedMachineWithinTheLimits) {
  const LoopCase param = GetParam();
  const auto start = std::chrono::steady_clock::now();
  auto nowS = [start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };

  // The simulated machine: a circle at 3000 mm/min in the middle of the travel.
  sim::Travel travel;
  sim::ErrorFunction trueError = sim::loadTrueError(modelFile(), &travel);
  sim::MachineOptions options;
  options.semantics = param.semantics;
  options.limits.maxOffsetMm = {0.5, 0.5, 0.5};
  // A realistic slew limit (the model offset changes by ~0.01 mm/s at this feed): an isolated
  // fault cycle (a late answer in the emulated guest) then removes only a few µm of offset.
  options.limits.maxRateMmS = {0.2, 0.2, 0.2};
  // SYNC waits for the answer inside the cycle: a longer period leaves room for an emulated guest.
  const std::chrono::milliseconds period = param.sync ? 20ms : 10ms;
  // The daemon limits the change per cycle by the time since its previous write, at most one
  // period; the simulator measures it with the arrival times it sees, which jitter by up to a
  // period in an emulated guest.
  options.limits.cycleS = std::chrono::duration<double>(period).count();
  options.limits.rateToleranceS = options.limits.cycleS;
  options.limits.quantumMm = {0.0001, 0.0001, 0.0001};
  options.settleS = 1.0;  // the offsets ramp in from zero at max_rate first
  sim::Machine machine(sim::Path::circle({425.0, 250.0, -250.0}, 150.0, 3000.0), trueError,
                       options);

  asio::io_context simIo;
  auto work = asio::make_work_guard(simIo);
  const CanLayout layout =
      config::loadCanLayout(loopConfig(param.sync), "can-loop.json", "transport");
  sim::CanSimNode node(
      simIo, layout,
      {[&](double t) { return machine.inputs(t); },
       [&](double t, const loop::OffsetCommand& c) { machine.onWrite(t, c); }, nowS},
      2ms);
  ASSERT_FALSE(node.start());
  // The error statistics are sampled every 5 ms on the simulator's thread.
  asio::steady_timer sampler(simIo);
  bool sampling = true;  // only touched on the simulator's thread
  std::function<void()> sampleTick = [&] {
    sampler.expires_at(sampler.expiry() + 5ms);
    sampler.async_wait([&](const std::error_code& ec) {
      // A completion already queued when the timer is cancelled still arrives without error.
      if (ec || !sampling) return;
      machine.sample(nowS());
      sampleTick();
    });
  };
  sampler.expires_at(std::chrono::steady_clock::now());
  sampleTick();
  std::thread simThread([&] { simIo.run(); });
  std::cout << "whole loop: simulator running" << std::endl;

  // The daemon side.
  loop::LoopSettings settings;
  settings.period = period;
  settings.limiter = volcomp::loop::LimiterSettings::uniform(0.5, 0.2);
  settings.staleTimeout = 200ms;
  settings.offsetReadback = true;
  settings.semantics = param.semantics;
  loop::SteadyClock clock;
  CanControllerPort port(layout);
  loop::CompensationLoop loop(port, clock, daemon::loadCompensationModel(modelFile()), settings);
  std::uint64_t activeCycles = 0;
  auto deadline = std::chrono::steady_clock::now();
  const auto runUntil = deadline + 5s;
  while (deadline < runUntil) {
    const loop::CycleReport report = loop.step();
    if (report.state == loop::LoopState::Active) ++activeCycles;
    deadline += settings.period;
    std::this_thread::sleep_until(deadline);  // the loop's own period, not test synchronisation
  }
  // The error statistics cover compensated running; the stop (offsets ramp out) comes after.
  const json report = machine.report(nowS());
  std::cout << "whole loop: " << activeCycles << " active cycles, stopping" << std::endl;
  stopAndWaitForTheLastWrite(loop, deadline, settings.period, machine);

  const json finalReport = machine.report(nowS());
  asio::post(simIo, [&] {
    sampling = false;
    sampler.cancel();
    node.stop();
  });
  work.reset();
  simThread.join();
  std::cout << "whole loop: simulator stopped" << std::endl;

  std::cout << "whole loop over CAN: " << report.dump() << "\n"
            << "driver: sets " << port.stats().completeSets << ", frames sent "
            << port.stats().framesSent << ", malformed " << port.stats().malformedFrames
            << ", dropped " << port.stats().txDropped << "; loop: active cycles " << activeCycles
            << ", read errors " << loop.counters().readErrors << "\n";
  const double uncompensated = report["rms_uncompensated_um"];
  const double compensated = report["rms_compensated_um"];
  std::cout << "whole loop: RMS " << uncompensated << " -> " << compensated << " um, reduction "
            << 100.0 * (1.0 - compensated / uncompensated) << " %" << std::endl;
  ASSERT_GT(uncompensated, 1.0);  // the machine has a real error to remove
  EXPECT_GE(1.0 - compensated / uncompensated, 0.95)
      << "RMS " << uncompensated << " -> " << compensated << " µm";
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  EXPECT_EQ(finalReport["limiter_violations"], 0) << finalReport["first_violation"];
  EXPECT_GT(activeCycles, param.sync ? 150u : 300u);
  // The daemon's last write is zero offsets with status 0 (stopping), and the controller holds it.
  const auto writes = machine.writes();
  ASSERT_FALSE(writes.empty());
  EXPECT_EQ(writes.back().status, 0);
  for (double o : writes.back().offsetMm) EXPECT_EQ(o, 0.0);
}

// A hostile node on the same bus, at full rate (as fast as the socket takes frames, no pause):
// short and remote frames on the input identifiers, 64-byte FD frames, unknown identifiers, and
// error frames announcing error-passive and bus-off, while the real controller keeps answering.
// The daemon faults (bus-off) and ramps out, never writes past the limiter, does not crash, and
// compensates again once the hostile node stops and the controller reports it restarted.
TEST(CanHostileNode, FaultsSafelyAndRecoversWhenThePeerBehaves) {
  const auto start = std::chrono::steady_clock::now();
  auto nowS = [start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  sim::Travel travel;
  sim::MachineOptions options;
  options.limits.maxOffsetMm = {0.5, 0.5, 0.5};
  options.limits.maxRateMmS = {0.2, 0.2, 0.2};
  options.limits.rateToleranceS = 0.010;
  options.limits.quantumMm = {0.0001, 0.0001, 0.0001};
  sim::Machine machine(sim::Path::circle({425.0, 250.0, -250.0}, 150.0, 3000.0),
                       sim::loadTrueError(modelFile(), &travel), options);
  asio::io_context simIo;
  auto work = asio::make_work_guard(simIo);
  const CanLayout layout = config::loadCanLayout(loopConfig(false), "can-loop.json", "transport");
  sim::CanSimNode node(
      simIo, layout,
      {[&](double t) { return machine.inputs(t); },
       [&](double t, const loop::OffsetCommand& c) { machine.onWrite(t, c); }, nowS},
      2ms);
  ASSERT_FALSE(node.start());
  std::thread simThread([&] { simIo.run(); });

  loop::LoopSettings settings;
  settings.period = 10ms;
  settings.limiter = volcomp::loop::LimiterSettings::uniform(0.5, 0.2);
  settings.staleTimeout = 200ms;
  settings.offsetReadback = true;
  // Recovery when the peer behaves is the point here; acknowledging a latched fault is tested
  // with the loop's fakes.
  settings.faultLatch = false;
  loop::SteadyClock clock;
  CanControllerPort port(layout);
  loop::CompensationLoop loop(port, clock, daemon::loadCompensationModel(modelFile()), settings);

  std::atomic<bool> quit{false};
  std::atomic<std::uint64_t> sent{0};
  auto flood = [&] {
    test::PeerSocket peer;
    if (!peer.ok()) return;
    const std::vector<std::uint8_t> two(2, 0xFF), eight(8, 0xA5), sixtyFour(64, 0x5A);
    std::vector<std::uint8_t> passive(8, 0);
    passive[1] = CAN_ERR_CRTL_RX_PASSIVE;
    while (!quit) {
      for (canid_t id : {0x100u, 0x101u, 0x102u}) {
        sent += peer.send(id, two) ? 1 : 0;                   // too short for its signals
        sent += peer.send(id | CAN_RTR_FLAG, {}) ? 1 : 0;     // remote request
        sent += peer.sendFd(id, sixtyFour) ? 1 : 0;           // oversized (FD on a classical link)
        sent += peer.send(id | CAN_EFF_FLAG, eight) ? 1 : 0;  // right id, other format
      }
      sent += peer.send(0x7FF, eight) ? 1 : 0;
      sent += peer.send(CAN_ERR_FLAG | CAN_ERR_CRTL, passive) ? 1 : 0;
      sent += peer.send(CAN_ERR_FLAG | CAN_ERR_BUSOFF, eight) ? 1 : 0;
    }
  };

  std::uint64_t activeBefore = 0, faultCycles = 0, activeAfter = 0;
  auto deadline = std::chrono::steady_clock::now();
  auto run = [&](std::chrono::milliseconds span, std::uint64_t& active, std::uint64_t* faults) {
    const auto until = deadline + span;
    while (deadline < until) {
      const loop::CycleReport report = loop.step();
      if (report.state == loop::LoopState::Active) ++active;
      if (faults && report.state == loop::LoopState::Fault) ++*faults;
      deadline += settings.period;
      std::this_thread::sleep_until(deadline);  // the loop's own period
    }
  };
  run(2000ms, activeBefore, nullptr);
  std::thread hostile(flood);
  std::uint64_t activeDuring = 0;
  run(2000ms, activeDuring, &faultCycles);
  quit = true;
  hostile.join();
  {
    // The controller restarted: error-active again.
    test::PeerSocket peer;
    ASSERT_TRUE(peer.ok());
    ASSERT_TRUE(peer.send(CAN_ERR_FLAG | CAN_ERR_RESTARTED, std::vector<std::uint8_t>(8, 0)));
  }
  run(3000ms, activeAfter, nullptr);
  stopAndWaitForTheLastWrite(loop, deadline, settings.period, machine);
  const json report = machine.report(nowS());
  asio::post(simIo, [&] { node.stop(); });
  work.reset();
  simThread.join();

  std::cout << "hostile node: " << sent << " frames sent; driver: malformed "
            << port.stats().malformedFrames << ", unknown " << port.stats().unknownFrames
            << ", error frames " << port.stats().errorFrames << ", bus-off events "
            << port.stats().busOffEvents << " (" << port.stats().busOffEndedByCarrier
            << " ended by the carrier without a restart report), receive-queue drops "
            << port.stats().receiveQueueDrops << ", error-passive ended after drops "
            << port.stats().errorPassiveEndedAfterDrops << "; loop: active " << activeBefore
            << " before, " << activeDuring << " during, " << activeAfter << " after, fault cycles "
            << faultCycles << std::endl;
  EXPECT_GT(sent, 1000u);
  EXPECT_GT(port.stats().malformedFrames, 100u);
  EXPECT_GT(port.stats().busOffEvents, 0u);
  EXPECT_GT(activeBefore, 50u);
  EXPECT_GT(faultCycles, 0u) << "the flood must fault the loop (bus-off)";
  EXPECT_GT(activeAfter, 100u) << "the loop must compensate again once the peer behaves";
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  const auto writes = machine.writes();
  ASSERT_FALSE(writes.empty());
  EXPECT_EQ(writes.back().status, 0);
  for (double o : writes.back().offsetMm) EXPECT_EQ(o, 0.0);
}

// Broadcast with `commanded` positions, and SYNC-triggered with `actual` positions (the read-back
// offset is subtracted before the model is evaluated).
INSTANTIATE_TEST_SUITE_P(Triggers, CanWholeLoop,
                         ::testing::Values(LoopCase{false, loop::PositionSemantics::Commanded},
                                           LoopCase{true, loop::PositionSemantics::Actual}),
                         [](const ::testing::TestParamInfo<LoopCase>& testInfo) {
                           return std::string(testInfo.param.sync ? "SyncActual"
                                                                  : "BroadcastCommanded");
                         });

}  // namespace
}  // namespace volcomp::can
