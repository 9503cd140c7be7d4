// The daemon's CAN cycle end to end on a (virtual) CAN interface, against the simulator's CAN node,
// with the example layout (config/examples/volcompd-can.json + vmc-can.dbc) and model
// (vmc-xyfz-21.json):
//
//   CanCycle/sync       t0 -> CompensationLoop::step(): send SYNC; the node answers with the
//                       three input frames; the driver assembles the consistent set; model,
//                       limiter; encode and send the two output frames -> the node has received
//                       the complete command (t1). Six frames on the bus per cycle.
//   CanCycle/broadcast  the node broadcasts its input frames every 1 ms by itself; step() takes
//                       the newest complete set, evaluates and writes; t1 as above.
//   CanCodecCycle       the same cycle's codec work alone (decode the three input frames, encode
//                       the two output frames), no socket: the ratio between the two separates
//                       the codec from the kernel, the sockets and the thread hand-over.
//
// Times are wall-clock (manual time = t1 - t0 per cycle); counters give the median and the 99th
// percentile of the end-to-end time (e2e_p50_us, e2e_p99_us) and of step() alone (step_p50_us,
// step_p99_us). On the bus, classical CAN at 1 Mbit/s carries an 8-byte frame in ~114 µs (135 µs
// worst case): a SYNC cycle's six frames take ~0.7 ms of wire time, which vcan does not model.
//
// Environment: VOLCOMP_CAN_IFACE (default vcan0), VOLCOMP_CAN_DATA (the examples folder; default
// the source tree's). Run inside the QEMU guest by bench/can/run_cycle_bench.sh.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>
#include <asio/executor_work_guard.hpp>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <nlohmann/json.hpp>

#include "volcomp/can/controller_port.hpp"
#include "volcomp/can/layout.hpp"
#include "volcomp/can/signal.hpp"
#include "volcomp/config/can_config.hpp"
#include "volcomp/daemon/configuration.hpp"
#include "volcomp/loop/compensation_loop.hpp"
#include "volcomp/loop/compensation_model.hpp"
#include "volcomp/loop/steady_clock.hpp"
#include "volcomp/sim/can_sim_node.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using volcomp::loop::AxisSample;
using volcomp::loop::OffsetCommand;

std::string env(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

std::string dataDir() {
  return env("VOLCOMP_CAN_DATA", VOLCOMP_EXAMPLES_DIR);
}

/// The example daemon transport on the benchmark's interface; `sync` switches to the SYNC trigger
/// (frame 0x080, answer within 20 ms).
volcomp::can::CanLayout exampleLayout(bool sync) {
  const std::string file = dataDir() + "/volcompd-can.json";
  std::ifstream in(file);
  nlohmann::json transport = nlohmann::json::parse(in)["transport"];
  transport["interface"] = env("VOLCOMP_CAN_IFACE", "vcan0");
  if (sync) {
    transport["trigger"] = "sync";
    transport["sync"] = {{"id", "0x080"}};
    transport["timeouts"]["response_ms"] = 20;
  }
  return volcomp::config::loadCanLayout(transport, file, "transport");
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

/// The controller's side on its own thread: a CanSimNode whose machine stands on a 100 mm circle
/// (moving a little on every sample) and applies what it receives.
class NodeThread {
 public:
  explicit NodeThread(const volcomp::can::CanLayout& layout)
      : work_(asio::make_work_guard(io_)),
        node_(io_, layout,
              {[this](double) { return sample(); },
               [this](double, const OffsetCommand& c) {
                 applied_ = c.offsetMm;
                 received_.store(Clock::now().time_since_epoch().count(),
                                 std::memory_order_relaxed);
                 heartbeat_.store(c.heartbeat, std::memory_order_release);
               },
               [] { return 0.0; }},
              1ms) {}

  std::error_code start() {
    if (auto ec = node_.start()) return ec;
    thread_ = std::thread([this] { io_.run(); });
    return {};
  }

  ~NodeThread() {
    if (thread_.joinable()) {
      asio::post(io_, [this] { node_.stop(); });
      work_.reset();
      thread_.join();
    }
  }

  /// Waits until the node has received the command carrying `heartbeat` (the heartbeat signal
  /// is 8 bits), at most `timeout`; returns when it arrived. Matching the heartbeat keeps a late
  /// command of an earlier cycle from being taken for this one.
  std::optional<Clock::time_point> waitFor(std::uint16_t heartbeat, Clock::time_point t0,
                                           Clock::duration timeout) const {
    const std::uint16_t want = heartbeat & 0xFF;
    while (heartbeat_.load(std::memory_order_acquire) != want) {
      if (Clock::now() - t0 > timeout) return std::nullopt;
      std::this_thread::yield();
    }
    return Clock::time_point(Clock::duration(received_.load(std::memory_order_relaxed)));
  }
  std::uint16_t lastHeartbeat() const { return heartbeat_.load(std::memory_order_acquire); }

 private:
  AxisSample sample() {  // on the node's thread
    angle_ += 0.001;
    AxisSample s;
    s.positionMm = {425.0 + 100.0 * std::cos(angle_), 250.0 + 100.0 * std::sin(angle_), -250.0};
    s.enable = true;
    s.homed = true;
    s.hasAppliedOffsets = true;
    s.appliedOffsetMm = applied_;
    s.hasSequence = true;
    s.sequence = ++sequence_;
    return s;
  }

  asio::io_context io_;
  asio::executor_work_guard<asio::io_context::executor_type> work_;
  volcomp::sim::CanSimNode node_;
  std::thread thread_;
  double angle_ = 0.0;
  std::uint16_t sequence_ = 0;
  std::array<double, 3> applied_{};
  std::atomic<Clock::rep> received_{0};
  std::atomic<std::uint16_t> heartbeat_{0xFFFF};
};

void canCycle(benchmark::State& state, bool sync) {
  std::unique_ptr<NodeThread> node;
  std::unique_ptr<volcomp::can::CanControllerPort> port;
  std::unique_ptr<volcomp::loop::CompensationLoop> loop;
  volcomp::loop::SteadyClock clock;
  try {
    const volcomp::can::CanLayout layout = exampleLayout(sync);
    node = std::make_unique<NodeThread>(layout);
    if (auto ec = node->start()) {
      state.SkipWithError(("cannot open the CAN interface: " + ec.message()).c_str());
      return;
    }
    volcomp::loop::LoopSettings settings;
    settings.limiter = volcomp::loop::LimiterSettings::uniform(0.1, 0.5);
    port = std::make_unique<volcomp::can::CanControllerPort>(layout);
    loop = std::make_unique<volcomp::loop::CompensationLoop>(
        *port, clock, volcomp::daemon::loadCompensationModel(dataDir() + "/vmc-xyfz-21.json"),
        settings);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  // Until the loop is active (connect, read back the applied offsets, ramp in).
  for (int i = 0; i < 500 && loop->state() != volcomp::loop::LoopState::Active; ++i) {
    loop->step();
    std::this_thread::sleep_for(2ms);  // the broadcast node needs time to send a first set
  }
  if (loop->state() != volcomp::loop::LoopState::Active) {
    state.SkipWithError("the loop did not become active");
    return;
  }
  std::vector<double> e2eUs, stepUs;
  e2eUs.reserve(static_cast<std::size_t>(state.max_iterations));
  stepUs.reserve(static_cast<std::size_t>(state.max_iterations));
  std::uint64_t lost = 0, faults = 0;
  // The loop increments the heartbeat once per step; the node has seen the warm-up's last one.
  std::uint16_t heartbeat = node->lastHeartbeat();
  for (auto _ : state) {
    ++heartbeat;
    const auto t0 = Clock::now();
    const volcomp::loop::CycleReport report = loop->step();
    const auto tStep = Clock::now();
    if (report.state != volcomp::loop::LoopState::Active) ++faults;
    // Wait for the node to have the whole command (both output frames), at most 1 s.
    const auto received = node->waitFor(heartbeat, t0, 1s);
    if (!received) {
      ++lost;
      heartbeat = node->lastHeartbeat();  // a cycle that wrote nothing: follow the node again
      state.SetIterationTime(1.0);
      continue;
    }
    const double e2e = std::chrono::duration<double>(*received - t0).count();
    state.SetIterationTime(e2e);
    e2eUs.push_back(e2e * 1e6);
    stepUs.push_back(std::chrono::duration<double, std::micro>(tStep - t0).count());
    if (!sync) std::this_thread::sleep_for(1ms);  // a new set arrives between broadcast cycles
  }
  state.counters["e2e_p50_us"] = percentile(e2eUs, 0.5);
  state.counters["e2e_p99_us"] = percentile(e2eUs, 0.99);
  state.counters["step_p50_us"] = percentile(stepUs, 0.5);
  state.counters["step_p99_us"] = percentile(stepUs, 0.99);
  state.counters["lost"] = static_cast<double>(lost);
  state.counters["fault_cycles"] = static_cast<double>(faults);
}

/// The driver alone with the SYNC trigger, no loop: read() (SYNC out, the three input frames back)
/// then write() of the two output frames, timed separately (read_p50_us, write_p50_us, ...) and
/// end to end to the node's receipt (e2e_*), to see where a SYNC cycle spends its time.
void canPortSync(benchmark::State& state) {
  std::unique_ptr<NodeThread> node;
  std::unique_ptr<volcomp::can::CanControllerPort> port;
  try {
    const volcomp::can::CanLayout layout = exampleLayout(true);
    node = std::make_unique<NodeThread>(layout);
    if (auto ec = node->start()) {
      state.SkipWithError(("cannot open the CAN interface: " + ec.message()).c_str());
      return;
    }
    port = std::make_unique<volcomp::can::CanControllerPort>(layout);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  if (auto ec = port->connect()) {
    state.SkipWithError(("connect: " + ec.message()).c_str());
    return;
  }
  std::vector<double> readUs, writeUs, e2eUs;
  readUs.reserve(static_cast<std::size_t>(state.max_iterations));
  writeUs.reserve(static_cast<std::size_t>(state.max_iterations));
  e2eUs.reserve(static_cast<std::size_t>(state.max_iterations));
  AxisSample sample;
  OffsetCommand command;
  std::uint64_t failed = 0, lost = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const std::error_code readError = port->read(sample);
    const auto tRead = Clock::now();
    command.offsetMm = {0.001, -0.002, 0.003};
    ++command.heartbeat;
    const std::error_code writeError = port->write(command);
    const auto tWrite = Clock::now();
    if (readError || writeError) ++failed;
    const auto received = node->waitFor(command.heartbeat, t0, 1s);
    if (!received) {
      ++lost;
      state.SetIterationTime(1.0);
      continue;
    }
    const double e2e = std::chrono::duration<double>(*received - t0).count();
    state.SetIterationTime(e2e);
    readUs.push_back(std::chrono::duration<double, std::micro>(tRead - t0).count());
    writeUs.push_back(std::chrono::duration<double, std::micro>(tWrite - tRead).count());
    e2eUs.push_back(e2e * 1e6);
  }
  state.counters["read_p50_us"] = percentile(readUs, 0.5);
  state.counters["read_p99_us"] = percentile(readUs, 0.99);
  state.counters["write_p50_us"] = percentile(writeUs, 0.5);
  state.counters["write_p99_us"] = percentile(writeUs, 0.99);
  state.counters["e2e_p50_us"] = percentile(e2eUs, 0.5);
  state.counters["e2e_p99_us"] = percentile(e2eUs, 0.99);
  state.counters["failed"] = static_cast<double>(failed);
  state.counters["lost"] = static_cast<double>(lost);
}

/// The codec work of one cycle with the example layout: decode every signal of the three input
/// frames, encode every signal of the two output frames.
void canCodecCycle(benchmark::State& state) {
  const volcomp::can::CanLayout layout = exampleLayout(false);
  std::vector<std::array<std::uint8_t, 8>> inputs(layout.inputFrames.size());
  std::vector<std::array<std::uint8_t, 8>> outputs(layout.outputFrames.size());
  // Input payloads holding plausible values (positions, flags, counters, read-back).
  for (std::size_t f = 0; f < layout.inputFrames.size(); ++f) {
    for (const auto& s : layout.inputFrames[f].signals) {
      const double v = s.spec.unit == "mm" ? 0.0123 : 1.0;
      if (volcomp::can::encode(s.spec, v, inputs[f])) {
        state.SkipWithError("cannot encode a test payload");
        return;
      }
    }
  }
  std::array<double, 16> values{};
  const std::array<double, 4> out{0.0123, -0.0456, 0.0789, 5.0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(inputs);
    std::size_t n = 0;
    for (std::size_t f = 0; f < layout.inputFrames.size(); ++f) {
      for (const auto& s : layout.inputFrames[f].signals) {
        benchmark::DoNotOptimize(volcomp::can::decode(s.spec, inputs[f], values[n++ % 16]));
      }
    }
    for (std::size_t f = 0; f < layout.outputFrames.size(); ++f) {
      outputs[f].fill(0);
      std::size_t k = 0;
      for (const auto& s : layout.outputFrames[f].signals) {
        benchmark::DoNotOptimize(volcomp::can::encode(s.spec, out[k++ % 4], outputs[f]));
      }
    }
    benchmark::DoNotOptimize(values);
    benchmark::DoNotOptimize(outputs);
  }
}

}  // namespace

BENCHMARK_CAPTURE(canCycle, sync, true)
    ->UseManualTime()
    ->Iterations(2000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(canCycle, broadcast, false)
    ->UseManualTime()
    ->Iterations(1000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(canPortSync)->UseManualTime()->Iterations(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(canCodecCycle)->Unit(benchmark::kNanosecond);

BENCHMARK_MAIN();
