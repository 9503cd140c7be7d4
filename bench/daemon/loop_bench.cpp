// One cycle of the daemon without I/O (the fakes from tests/loop stand in for the controller):
// what the loop itself adds to a transaction that costs ~15-20 us on loopback Modbus TCP.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "fakes.hpp"
#include "volcomp/daemon/configuration.hpp"
#include "volcomp/loop/compensation_loop.hpp"
#include "volcomp/loop/limiter.hpp"

namespace {

using namespace volcomp::loop;
using namespace volcomp::loop::testing;
using volcomp::daemon::loadCompensationModel;

LoopSettings benchSettings() {
  LoopSettings s;
  s.period = std::chrono::milliseconds(1);
  s.limiter = LimiterSettings::uniform(0.5, 1.0, 100.0);
  return s;
}

void BM_LimiterStep(benchmark::State& state) {
  LimiterSettings s = benchSettings().limiter;
  LimiterState ls;
  std::array<double, 3> target{0.01, -0.02, 0.03};
  for (auto _ : state) {
    target[0] = -target[0];
    benchmark::DoNotOptimize(limitStep(s, ls, target, 0.001));
  }
}
BENCHMARK(BM_LimiterStep);

void runLoop(benchmark::State& state, std::shared_ptr<CompensationModel> model) {
  FakeClock clock;
  FakePort port;
  port.sample.positionMm = {400.0, 250.0, -200.0};
  CompensationLoop loop(port, clock, std::move(model), benchSettings());
  double dx = 0.05;
  for (auto _ : state) {
    port.sample.positionMm[0] += dx;
    if (port.sample.positionMm[0] > 450.0 || port.sample.positionMm[0] < 50.0) dx = -dx;
    clock.advance(std::chrono::milliseconds(1));
    benchmark::DoNotOptimize(loop.step());
  }
  if (loop.state() != LoopState::Active) state.SkipWithError("loop left the active state");
}

void BM_LoopStepFakeModel(benchmark::State& state) {
  runLoop(state, std::make_shared<FakeModel>());
}
BENCHMARK(BM_LoopStepFakeModel);

void BM_LoopStepVmc21(benchmark::State& state) {
  runLoop(state, loadCompensationModel(std::string(VOLCOMP_EXAMPLES_DIR) + "/vmc-xyfz-21.json"));
}
BENCHMARK(BM_LoopStepVmc21);

}  // namespace

BENCHMARK_MAIN();
