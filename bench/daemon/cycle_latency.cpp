// volcomp-bench-cycle: latency of one compensation cycle of volcompd's loop (read the inputs,
// evaluate the model, limit, write the outputs: CompensationLoop::step() over the real Modbus
// port) beside the bare libmodbus transaction that moves the same registers (one FC03 of the
// read block + one FC16 of the write block), against the same Modbus server in the same run.
//
// The two are measured in alternating rounds (the simulated controller serves one client at a
// time, so each round connects, measures, disconnects), paced on absolute deadlines like the
// daemon (a CPU left idle between cycles wakes up as it would in service). Only cycles that
// start and end in the Active state are counted (no connect/read-back cycles).
// Pin this process and the server (taskset) for meaningful figures; see run_latency.sh.

#include <modbus/modbus.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "volcomp/daemon/daemon.hpp"
#include "volcomp/loop/compensation_loop.hpp"
#include "volcomp/loop/loop_settings.hpp"
#include "volcomp/loop/steady_clock.hpp"
#include "volcomp/modbus/controller_port.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using volcomp::loop::LoopState;

struct Summary {
  double medianUs = 0, p99Us = 0, p999Us = 0, maxUs = 0, meanUs = 0;
  std::size_t n = 0;
};

Summary summarise(std::vector<double> us) {
  Summary s;
  s.n = us.size();
  if (us.empty()) return s;
  std::sort(us.begin(), us.end());
  auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(q * static_cast<double>(us.size() - 1) + 0.5);
    return us[std::min(i, us.size() - 1)];
  };
  s.medianUs = at(0.5);
  s.p99Us = at(0.99);
  s.p999Us = at(0.999);
  s.maxUs = us.back();
  double sum = 0;
  for (double v : us) sum += v;
  s.meanUs = sum / static_cast<double>(us.size());
  return s;
}

nlohmann::json toJson(const Summary& s) {
  return {{"n", s.n},          {"median_us", s.medianUs},
          {"p99_us", s.p99Us}, {"p99_9_us", s.p999Us},
          {"max_us", s.maxUs}, {"mean_us", s.meanUs}};
}

double microseconds(Clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

/// Steps the loop on the pacing grid until it is Active (connect, read back, first write).
bool stepUntilActive(volcomp::loop::CompensationLoop& loop, Clock::time_point& next,
                     Clock::duration period, int maxCycles) {
  for (int i = 0; i < maxCycles; ++i) {
    std::this_thread::sleep_until(next);
    next += period;
    loop.step();
    if (loop.state() == LoopState::Active) return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "volcomp-bench-cycle: volcompd's cycle (read, model, write) vs the bare libmodbus "
      "FC03+FC16 transaction, against the same Modbus TCP server"};
  std::string configPath;
  int samples = 20000;
  int rounds = 10;
  int periodUs = 1000;
  int port = -1;
  app.add_option("-c,--config", configPath, "volcompd configuration (modbus-tcp)")->required();
  app.add_option("--port", port, "TCP port of the server (overrides the configuration's)");
  app.add_option("--samples", samples, "cycles measured per kind (split over the rounds)")
      ->check(CLI::PositiveNumber);
  app.add_option("--rounds", rounds, "alternating rounds of each kind")->check(CLI::PositiveNumber);
  app.add_option("--period-us", periodUs, "pacing period (absolute deadlines)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  try {
    volcomp::daemon::LoadedConfiguration loaded = volcomp::daemon::loadConfiguration(configPath);
    auto* modbusSettings = std::get_if<volcomp::modbus::ModbusSettings>(&loaded.config.transport);
    auto* tcp =
        modbusSettings ? std::get_if<volcomp::modbus::TcpLink>(&modbusSettings->link) : nullptr;
    if (tcp == nullptr) throw std::runtime_error("the harness measures modbus-tcp only");
    if (port >= 0) tcp->port = static_cast<std::uint16_t>(port);
    const volcomp::modbus::ModbusSettings& modbusConfig = *modbusSettings;
    volcomp::modbus::ModbusControllerPort controllerPort(modbusConfig);
    const volcomp::modbus::RegisterPlan plan = controllerPort.plan();
    if (plan.inputRead.count != 0 || modbusConfig.registers.fc23) {
      throw std::runtime_error(
          "the bare transaction mirrors FC03 + FC16: use a holding-only map "
          "without fc23");
    }
    volcomp::loop::SteadyClock clock;
    const Clock::duration period = std::chrono::microseconds(periodUs);
    const int perRound = std::max(1, samples / rounds);
    std::vector<double> cycleUs, bareUs, wakeLateUs;
    cycleUs.reserve(static_cast<std::size_t>(perRound * rounds));
    bareUs.reserve(static_cast<std::size_t>(perRound * rounds));
    wakeLateUs.reserve(static_cast<std::size_t>(perRound * rounds));
    std::uint64_t bareErrors = 0, cycleNotActive = 0;
    std::vector<std::uint16_t> readBuffer(plan.holdingRead.count), writeBuffer(plan.write.count);

    for (int r = 0; r < rounds; ++r) {
      // Daemon cycles: a fresh loop per round (it connects and reads the offsets back first).
      {
        volcomp::loop::CompensationLoop loop(controllerPort, clock, loaded.model,
                                             volcomp::daemon::loopSettingsFrom(loaded.config));
        Clock::time_point next = Clock::now();
        if (!stepUntilActive(loop, next, period, 5000)) {
          throw std::runtime_error("the loop did not become active (is the server running?)");
        }
        for (int i = 0; i < perRound; ++i) {
          std::this_thread::sleep_until(next);
          const auto t0 = Clock::now();
          // How late the thread woke for its deadline: the platform's share of an overrun.
          wakeLateUs.push_back(microseconds(t0 - next));
          next += period;
          loop.step();
          const auto t1 = Clock::now();
          if (loop.state() == LoopState::Active) {
            cycleUs.push_back(microseconds(t1 - t0));
          } else {
            ++cycleNotActive;
          }
        }
        controllerPort.disconnect();
      }
      // Bare libmodbus: the same registers, one FC03 and one FC16 per transaction.
      {
        modbus_t* ctx = modbus_new_tcp(tcp->host.c_str(), tcp->port);
        if (ctx == nullptr) throw std::runtime_error("modbus_new_tcp failed");
        std::unique_ptr<modbus_t, void (*)(modbus_t*)> guard(ctx, [](modbus_t* c) {
          modbus_close(c);
          modbus_free(c);
        });
        modbus_set_slave(ctx, modbusConfig.slaveId);
        modbus_set_response_timeout(ctx, 0, 500000);
        // The server accepts the next client once it has seen the previous one close.
        bool connected = false;
        for (int attempt = 0; attempt < 200 && !connected; ++attempt) {
          connected = modbus_connect(ctx) == 0;
          if (!connected) std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        if (!connected) throw std::runtime_error("bare client: cannot connect");
        Clock::time_point next = Clock::now();
        for (int i = 0; i < perRound; ++i) {
          std::this_thread::sleep_until(next);
          next += period;
          const auto t0 = Clock::now();
          const int rd = modbus_read_registers(ctx, plan.holdingRead.start, plan.holdingRead.count,
                                               readBuffer.data());
          const int wr =
              modbus_write_registers(ctx, plan.write.start, plan.write.count, writeBuffer.data());
          const auto t1 = Clock::now();
          if (rd == plan.holdingRead.count && wr == plan.write.count) {
            bareUs.push_back(microseconds(t1 - t0));
          } else {
            ++bareErrors;
          }
        }
      }
    }

    const Summary cycle = summarise(cycleUs);
    const Summary bare = summarise(bareUs);
    const Summary wakeLate = summarise(wakeLateUs);
    const nlohmann::json result{
        {"period_us", periodUs},
        {"rounds", rounds},
        {"read_registers", plan.holdingRead.count},
        {"write_registers", plan.write.count},
        {"model", loaded.model->name()},
        {"daemon_cycle", toJson(cycle)},
        {"bare_fc03_fc16", toJson(bare)},
        {"wake_late", toJson(wakeLate)},
        {"cycles_not_active", cycleNotActive},
        {"bare_errors", bareErrors},
        {"ratio_median", bare.medianUs > 0 ? cycle.medianUs / bare.medianUs : 0.0},
        {"ratio_p99", bare.p99Us > 0 ? cycle.p99Us / bare.p99Us : 0.0},
    };
    std::printf("%s\n", result.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "volcomp-bench-cycle: %s\n", e.what());
    return 1;
  }
}
