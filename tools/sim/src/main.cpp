// volcomp-sim: the simulated machine and controller (docs/modbus.md, "volcomp-sim"), served over
// Modbus TCP/RTU or CAN. See docs/modbus.md and docs/can.md for usage; the report is one JSON line
// on stdout at the end (and a readable summary on stderr).
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/display_units.hpp"
#include "volcomp/format/text.hpp"
#include "volcomp/sim/can_server.hpp"
#include "volcomp/sim/commands.hpp"
#include "volcomp/sim/machine.hpp"
#include "volcomp/sim/modbus_server.hpp"
#include "volcomp/sim/nc_run.hpp"
#include "volcomp/sim/sim_config.hpp"

namespace {

std::atomic<bool> gStop{false};

extern "C" void onSignal(int) {
  gStop = true;
}

void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
}

/// Non-blocking line reader for run-time commands on stdin.
class StdinCommands {
 public:
  /// Returns complete lines available now (never blocks).
  std::vector<std::string> poll() {
    std::vector<std::string> lines;
    if (eof_) return lines;
    pollfd p{STDIN_FILENO, POLLIN, 0};
    while (::poll(&p, 1, 0) > 0 && (p.revents & (POLLIN | POLLHUP)) != 0) {
      char buf[512];
      const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
      if (n <= 0) {
        eof_ = true;
        break;
      }
      pending_.append(buf, static_cast<std::size_t>(n));
    }
    std::size_t nl;
    while ((nl = pending_.find('\n')) != std::string::npos) {
      lines.push_back(pending_.substr(0, nl));
      pending_.erase(0, nl + 1);
    }
    return lines;
  }

 private:
  std::string pending_;
  bool eof_ = false;
};

void writeRecord(const std::string& file, const std::vector<volcomp::sim::WriteRecord>& writes) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file + ": cannot write the record");
  out << "t_s,offset_x_mm,offset_y_mm,offset_z_mm,status,heartbeat,partial,violation\n";
  out << std::setprecision(17);
  for (const auto& w : writes) {
    out << w.timeS << ',' << w.offsetMm[0] << ',' << w.offsetMm[1] << ',' << w.offsetMm[2] << ','
        << w.status << ',' << w.heartbeat << ',' << (w.partial ? 1 : 0) << ','
        << (w.violation ? 1 : 0) << '\n';
  }
}

// Faults of Modbus requests and replies; a CAN node has no replies to delay or drop.
bool modbusOnly(volcomp::sim::Command::Kind kind) {
  using Kind = volcomp::sim::Command::Kind;
  return kind == Kind::Exception || kind == Kind::LateReply || kind == Kind::NoReply ||
         kind == Kind::PauseClient;
}

bool pathInsideTravel(const volcomp::sim::Path& path, const volcomp::sim::Travel& travel,
                      std::string& why) {
  const auto b = path.bounds();
  constexpr const char* axes = "XYZ";
  for (std::size_t k = 0; k < 3; ++k) {
    if (!travel[k]) continue;
    const auto& t = *travel[k];
    if (b[0][k] < t[0] - 1e-9 || b[1][k] > t[1] + 1e-9) {
      why = std::string("the path leaves the travel of axis ") + axes[k] + " [" +
            std::to_string(t[0]) + ", " + std::to_string(t[1]) + "]: it spans [" +
            std::to_string(b[0][k]) + ", " + std::to_string(b[1][k]) + "]";
      return false;
    }
  }
  return true;
}

// The report for people, on stderr: um to 4 significant digits (stdout keeps the JSON line with
// full precision for programs).
void printSummary(const nlohmann::json& r) {
  const auto um = [](const nlohmann::json& v) {
    return v.is_number() ? volcomp::config::significant(v.get<double>()) : std::string("-");
  };
  std::cerr << "volcomp-sim: summary over " << um(r.value("duration_s", 0.0)) << " s, "
            << r.value("samples", 0) << " samples of the tool-tip error (um)\n"
            << "              RMS before   RMS after  max before   max after\n";
  const auto row = [&](const std::string& name, const nlohmann::json& v) {
    using volcomp::format::padLeft;
    // One write per line: stderr is unbuffered.
    std::cerr << "  " + volcomp::format::padRight(name, 6) + ' ' +
                     padLeft(um(v["rms_uncompensated_um"]), 14) + ' ' +
                     padLeft(um(v["rms_compensated_um"]), 11) + ' ' +
                     padLeft(um(v["max_uncompensated_um"]), 11) + ' ' +
                     padLeft(um(v["max_compensated_um"]), 11) + '\n';
  };
  if (r.contains("axes")) {
    for (const char* axis : {"X", "Y", "Z"}) {
      if (r["axes"].contains(axis)) row(axis, r["axes"][axis]);
    }
  }
  row("|e|", r);
  std::cerr << "  writes " << r.value("writes", 0) << ", limiter violations "
            << r.value("limiter_violations", 0) << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  // `volcomp-sim nc-run ...`: an NC program on the simulated machine, without a controller link.
  if (argc > 1 && std::string(argv[1]) == "nc-run")
    return volcomp::sim::ncRunMain(argc - 1, argv + 1);
  CLI::App app{"volcomp-sim: a simulated machine and controller for volcompd (Modbus TCP/RTU, CAN)",
               "volcomp-sim"};
  app.set_version_flag("--version", std::string("volcomp-sim ") + VOLCOMP_VERSION);
  app.footer(
      "Fault commands (stdin, one per line, or --event T:COMMAND[:ARG...]): stall [S], "
      "drop-link [S], exception CODE [S], late-reply S [N], no-reply [N], pause-client PID S, "
      "garble-readback MM [S], freeze [S], hold [S], enable on|off, homed on|off, ack on|off, "
      "resume, status, quit.\n"
      "CAN: stall and drop-link both make the node silent (socket closed: no input frames, no SYNC "
      "answers, writes not received) and it reopens when they end; taking the interface down "
      "(ip link set DEV down) is outside the simulator. exception, late-reply, no-reply and "
      "pause-client are Modbus only.\n");
  std::string configFile, recordFile, modelOverride, semanticsOverride, interfaceOverride;
  std::optional<int> port;
  bool rtu = false, tcp = false;
  double durationS = 0.0;
  std::vector<std::string> eventSpecs;
  app.add_option("--config,-c", configFile, "simulator configuration (JSON)")->required();
  app.add_option("--port", port, "TCP port on 127.0.0.1 (0 = a free port; default: the config's)")
      ->check(CLI::Range(0, 65535));
  auto* rtuFlag = app.add_flag("--rtu", rtu, "serve Modbus RTU on a new pseudo-terminal");
  app.add_flag("--tcp", tcp, "serve Modbus TCP whatever the config's transport type")
      ->excludes(rtuFlag);
  app.add_option("--duration", durationS, "run this many seconds (0 = until SIGTERM/quit)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--record", recordFile, "write every write received as CSV to this file");
  app.add_option("--event", eventSpecs,
                 "scheduled fault T:COMMAND[:ARG...], e.g. 2:drop-link:1.5 (repeatable)");
  app.add_option("--interface", interfaceOverride,
                 "CAN: SocketCAN interface (overrides the transport's \"interface\")");
  app.add_option("--model", modelOverride, "true error model (overrides the config's)");
  app.add_option("--semantics", semanticsOverride, "position semantics (overrides the config's)")
      ->check(CLI::IsMember({"commanded", "actual"}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  using namespace volcomp;
  std::optional<sim::Machine> machine;
  std::vector<sim::ScheduledEvent> events;
  sim::SimConfig cfg;
  try {
    for (const auto& spec : eventSpecs) events.push_back(sim::parseEvent(spec));
    std::stable_sort(events.begin(), events.end(),
                     [](const auto& a, const auto& b) { return a.atS < b.atS; });
    cfg = sim::loadSimConfig(configFile);
    if (!modelOverride.empty()) cfg.modelPath = modelOverride;
    if (!semanticsOverride.empty()) {
      cfg.machine.semantics = semanticsOverride == "actual" ? loop::PositionSemantics::Actual
                                                            : loop::PositionSemantics::Commanded;
    }
    sim::Path path = sim::makePath(cfg.path);
    sim::ErrorFunction trueError = [](const sim::Vec3&, const sim::MotionDirections&) {
      return sim::Vec3{};
    };
    if (cfg.modelPath) {
      sim::Travel travel{};
      trueError = sim::loadTrueError(*cfg.modelPath, &travel);
      std::string why;
      if (!pathInsideTravel(path, travel, why)) throw config::ConfigError(configFile, "path", why);
    }
    if (auto* layout = std::get_if<can::CanLayout>(&cfg.transport)) {
      if (rtu || tcp || port) {
        throw config::ConfigError(configFile, "transport.type",
                                  "--rtu, --tcp and --port apply to Modbus, not to \"can\"");
      }
      for (const auto& e : events) {
        if (modbusOnly(e.command.kind)) {
          throw config::ConfigError(configFile, "transport.type",
                                    "exception, late-reply, no-reply and pause-client are Modbus "
                                    "only (not with \"can\")");
        }
      }
      if (!interfaceOverride.empty()) {
        if (interfaceOverride.size() > 15) {
          throw config::ConfigError("--interface", "", "expected 1-15 characters");
        }
        layout->interfaceName = interfaceOverride;
      }
    } else if (!interfaceOverride.empty()) {
      throw config::ConfigError(configFile, "transport.type",
                                "--interface applies to \"can\", not to Modbus");
    }
    // Long runs without --record keep counters only.
    cfg.machine.keepWrites = !recordFile.empty();
    machine.emplace(std::move(path), std::move(trueError), cfg.machine);
  } catch (const std::exception& e) {
    std::cerr << "volcomp-sim: " << e.what() << '\n';
    return 2;
  }

  installSignalHandlers();
  const auto start = std::chrono::steady_clock::now();
  auto now = [start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::optional<sim::ModbusServer> modbusServer;
  std::optional<sim::CanServer> canServer;
  try {
    if (const auto* layout = std::get_if<can::CanLayout>(&cfg.transport)) {
      canServer.emplace(*layout, *machine, now,
                        std::chrono::microseconds(std::llround(cfg.canBroadcastS * 1e6)));
      canServer->start();
      std::cout << canServer->listeningLine() << std::endl;
    } else {
      const auto& modbusConfig = std::get<modbus::ModbusSettings>(cfg.transport);
      modbusServer.emplace(modbusConfig.registers, modbusConfig.slaveId, *machine, now);
      const bool serveRtu =
          rtu || (!tcp && std::holds_alternative<modbus::RtuLink>(modbusConfig.link));
      if (serveRtu) {
        modbusServer->startRtu();
      } else {
        std::uint16_t p = 0;
        if (port) {
          p = static_cast<std::uint16_t>(*port);
        } else if (const auto* t = std::get_if<modbus::TcpLink>(&modbusConfig.link)) {
          p = t->port;
        }
        modbusServer->startTcp(p);
      }
      std::cout << modbusServer->listeningLine() << std::endl;
    }
  } catch (const std::exception& e) {
    std::cerr << "volcomp-sim: " << e.what() << '\n';
    return 1;
  }

  StdinCommands stdinCommands;
  std::size_t nextEvent = 0;
  const auto tick = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(cfg.tickS));
  auto next = std::chrono::steady_clock::now();
  bool running = true;
  while (running && !gStop) {
    const double t = now();
    while (running && nextEvent < events.size() && events[nextEvent].atS <= t) {
      std::cerr << "volcomp-sim: t=" << t << " s: event at " << events[nextEvent].atS << " s\n";
      running = sim::applyCommand(*machine, t, events[nextEvent].command);
      ++nextEvent;
    }
    for (const std::string& line : stdinCommands.poll()) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      try {
        const sim::Command command = sim::parseCommand(line);
        if (canServer && modbusOnly(command.kind)) {
          std::cerr << "volcomp-sim: " << line << ": Modbus only, ignored on CAN\n";
          continue;
        }
        if (command.kind == sim::Command::Kind::Status) {
          std::cout << "STATUS " << machine->report(t).dump() << std::endl;
          continue;
        }
        running = sim::applyCommand(*machine, t, command) && running;
        std::cerr << "volcomp-sim: t=" << t << " s: " << line << '\n';
      } catch (const std::invalid_argument& e) {
        std::cerr << "volcomp-sim: " << e.what() << '\n';
      }
    }
    machine->sample(t);
    if (canServer) canServer->update(t);
    if (durationS > 0.0 && t >= durationS) break;
    next += tick;
    const auto late = std::chrono::steady_clock::now();
    if (next < late) next = late;  // a late tick does not cause a burst of catch-up samples
    std::this_thread::sleep_until(next);
  }
  if (modbusServer) modbusServer->stop();
  if (canServer) canServer->stop();
  const double end = now();
  int status = 0;
  if (!recordFile.empty()) {
    try {
      writeRecord(recordFile, machine->writes());
    } catch (const std::exception& e) {
      std::cerr << "volcomp-sim: " << e.what() << '\n';
      status = 1;
    }
  }
  nlohmann::json report = machine->report(end);
  if (canServer) report["can"] = canServer->counters();
  std::cout << report.dump() << std::endl;
  printSummary(report);
  return status;
}
