// volcomp-bench-server: the Modbus server role's transaction time against the client role's, on
// loopback TCP, same register map (the example's: inputs 0..13, outputs 14..21), same two
// transactions per cycle (one FC16 of the inputs / FC03 of the outputs, or FC03 + FC16 in the
// client role), one process:
//   client role: volcompd's ModbusControllerPort read()+write() -> a bare libmodbus server
//   server role: a bare libmodbus master (FC16 inputs + FC03 outputs) -> volcompd's
//                ModbusServerPort (the loop side copying inputs out and outputs in each cycle)
//   baseline:    bare libmodbus master -> bare libmodbus server
// Rounds of each alternate (so that load drift hits all three); cycles are paced on absolute
// 1 ms deadlines like the daemon. Prints medians, p99 and the ratios. Pin it (taskset) for
// figures; the README quotes a run with `taskset -c 1`.

#include <arpa/inet.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "volcomp/modbus/controller_port.hpp"
#include "volcomp/modbus/server_port.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace volcomp;

modbus::RegisterMap exampleMap() {
  modbus::RegisterMap m;
  for (std::uint16_t k = 0; k < 3; ++k) {
    m.position[k].address = static_cast<std::uint16_t>(2 * k);
    m.offset[k].address = static_cast<std::uint16_t>(14 + 2 * k);
  }
  m.enable = {modbus::RegisterTable::Holding, 6, 0};
  m.homed = {modbus::RegisterTable::Holding, 6, 1};
  m.sequence = modbus::WordRegister{modbus::RegisterTable::Holding, 7};
  std::array<modbus::ValueRegister, 3> applied{};
  for (std::uint16_t k = 0; k < 3; ++k) applied[k].address = static_cast<std::uint16_t>(8 + 2 * k);
  m.appliedOffset = applied;
  m.statusAddress = 20;
  m.heartbeatAddress = 21;
  return m;
}

/// A bare libmodbus TCP server on 127.0.0.1 (port chosen by the system), one client at a time.
class BareServer {
 public:
  BareServer() : ctx_(modbus_new_tcp("127.0.0.1", 0)), mapping_(modbus_mapping_new(0, 0, 22, 0)) {
    listen_ = modbus_tcp_listen(ctx_, 1);
    sockaddr_in addr{};
    socklen_t len = sizeof addr;
    getsockname(listen_, reinterpret_cast<sockaddr*>(&addr), &len);
    port = ntohs(addr.sin_port);
    stop_ = ::eventfd(0, EFD_CLOEXEC);
    thread_ = std::thread([this] { serve(); });
  }
  ~BareServer() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(stop_, &one, sizeof one);
    thread_.join();
    ::close(listen_);
    ::close(stop_);
    modbus_mapping_free(mapping_);
    modbus_free(ctx_);
  }
  int port = 0;

 private:
  void serve() {
    std::array<std::uint8_t, MODBUS_TCP_MAX_ADU_LENGTH> query{};
    int client = -1;
    while (true) {
      pollfd fds[2] = {{stop_, POLLIN, 0}, {client >= 0 ? client : listen_, POLLIN, 0}};
      if (::poll(fds, 2, -1) <= 0) continue;
      if (fds[0].revents != 0) break;
      if (client < 0) {
        client = ::accept(listen_, nullptr, nullptr);
        int one = 1;  // as volcompd's server: replies in one segment
        setsockopt(client, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        continue;
      }
      modbus_set_socket(ctx_, client);
      const int rc = modbus_receive(ctx_, query.data());
      if (rc < 0) {
        ::close(client);
        client = -1;
      } else if (rc > 0) {
        modbus_reply(ctx_, query.data(), rc, mapping_);
      }
    }
    if (client >= 0) ::close(client);
    modbus_set_socket(ctx_, -1);
  }
  modbus_t* ctx_;
  modbus_mapping_t* mapping_;
  int listen_ = -1;
  int stop_ = -1;
  std::thread thread_;
};

/// Paces `cycle` on absolute deadlines `period` apart; returns each cycle's duration in us.
template <typename Cycle>
void timed(int cycles, std::chrono::microseconds period, std::vector<double>& out, Cycle&& cycle) {
  auto deadline = Clock::now();
  for (int i = 0; i < cycles; ++i) {
    deadline += period;
    while (Clock::now() < deadline) {
      // Busy wait: a sleeping thread's wake-up latency would be measured along with the cycle.
    }
    const auto t0 = Clock::now();
    if (!cycle()) continue;
    out.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Modbus server role vs client role: transaction time on loopback TCP",
               "volcomp-bench-server"};
  int cycles = 20000;
  int rounds = 10;
  int periodUs = 1000;
  app.add_option("--cycles", cycles, "cycles per role in total")->check(CLI::Range(100, 10000000));
  app.add_option("--rounds", rounds, "alternating rounds")->check(CLI::Range(1, 1000));
  app.add_option("--period-us", periodUs, "cycle period (absolute deadlines)")
      ->check(CLI::Range(100, 100000));
  CLI11_PARSE(app, argc, argv);

  const modbus::RegisterMap map = exampleMap();
  std::vector<double> clientRole, serverRole, baseline;
  std::array<std::uint16_t, 14> inputs{};
  std::array<std::uint16_t, 8> outputs{};
  inputs[6] = 3;
  loop::AxisSample sample;
  loop::OffsetCommand command;
  const int perRound = cycles / rounds;
  const std::chrono::microseconds period(periodUs);
  // A bare libmodbus master: FC16 of the inputs, FC03 of the outputs, per cycle.
  const auto masterCycles = [&](int port, std::vector<double>& out) {
    modbus_t* master = modbus_new_tcp("127.0.0.1", port);
    const bool up = modbus_connect(master) == 0;
    if (up) {
      timed(perRound, period, out, [&] {
        ++inputs[7];
        return modbus_write_registers(master, 0, 14, inputs.data()) == 14 &&
               modbus_read_registers(master, 14, 8, outputs.data()) == 8;
      });
    }
    modbus_close(master);
    modbus_free(master);
    return up;
  };

  for (int round = 0; round < rounds; ++round) {
    {
      BareServer server;
      modbus::ModbusSettings s;
      s.link = modbus::TcpLink{"127.0.0.1", static_cast<std::uint16_t>(server.port)};
      s.registers = map;
      s.responseTimeoutMs = 1000;
      modbus::ModbusControllerPort port(s);
      if (port.connect()) return 1;
      timed(perRound, period, clientRole, [&] {
        ++command.heartbeat;
        return !port.read(sample) && !port.write(command);
      });
    }
    {
      modbus::ModbusSettings s;
      s.role = modbus::ModbusRole::Server;
      s.link = modbus::TcpLink{"127.0.0.1", 0};
      s.registers = map;
      modbus::ModbusServerPort port(s);
      // The loop side, as the daemon's cycle does it after each complete position set (here on
      // the server's own thread instead of the daemon's io thread).
      port.setCycleTrigger([&] {
        loop::AxisSample in;
        loop::OffsetCommand out;
        if (!port.read(in)) port.write(out);
      });
      if (port.connect()) return 1;
      if (!masterCycles(port.boundPort(), serverRole)) return 1;
    }
    {
      BareServer server;
      if (!masterCycles(server.port, baseline)) return 1;
    }
  }
  const double c = quantile(clientRole, 0.5), sv = quantile(serverRole, 0.5),
               b = quantile(baseline, 0.5);
  std::printf("cycles per role %zu/%zu/%zu, period %d us\n", clientRole.size(), serverRole.size(),
              baseline.size(), periodUs);
  std::printf("client role (volcompd port -> libmodbus server): median %.1f us, p99 %.1f us\n", c,
              quantile(clientRole, 0.99));
  std::printf("server role (libmodbus master -> volcompd server): median %.1f us, p99 %.1f us\n",
              sv, quantile(serverRole, 0.99));
  std::printf("baseline (libmodbus master -> libmodbus server): median %.1f us, p99 %.1f us\n", b,
              quantile(baseline, 0.99));
  std::printf("server / client role %.2f x, server role / baseline %.2f x\n", sv / c, sv / b);
  return 0;
}
