// volcompd: the live compensation daemon. Reads the configuration, builds the driver named in it,
// and runs the compensation loop until SIGTERM/SIGINT (ramp-out, exit 0); SIGHUP reloads. Shared
// by volcompd and volcompd-linuxcnc, which differ only in the transports they have (program.hpp).
// Exit status: 0 after a clean stop or a good --check-config, 1 on a runtime failure, 2 on bad
// arguments or a bad configuration/model file.

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <asio/io_context.hpp>
#include <asio/post.hpp>
#include <asio/signal_set.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <memory>
#include <string>
#include <variant>

#include "commissioning.hpp"
#include "environment_check.hpp"
#include "program.hpp"
#include "transports.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/daemon/daemon.hpp"
#include "volcomp/daemon/notifier.hpp"
#include "volcomp/daemon/waitable_clock.hpp"

namespace {

// systemd sets JOURNAL_STREAM to "<device>:<inode>" of the journal stream it connected stderr to
// (systemd.exec(5)); compared with stderr itself, so that a redirected stderr is honoured.
bool stderrIsTheJournal() {
  const char* stream = std::getenv("JOURNAL_STREAM");
  struct stat st {};
  unsigned long long device = 0, inode = 0;
  return stream != nullptr && std::sscanf(stream, "%llu:%llu", &device, &inode) == 2 &&
         ::fstat(STDERR_FILENO, &st) == 0 && device == st.st_dev && inode == st.st_ino;
}

void setUpLogging() {
  std::shared_ptr<spdlog::logger> logger;
  if (stderrIsTheJournal()) {
    // Straight into the journal, each message with its priority; journald stamps time and unit.
    logger = std::make_shared<spdlog::logger>(
        "volcompd", std::make_shared<spdlog::sinks::systemd_sink_mt>("volcompd"));
  } else {
    logger = std::make_shared<spdlog::logger>("volcompd",
                                              std::make_shared<spdlog::sinks::stderr_sink_mt>());
    logger->set_pattern("%Y-%m-%d %H:%M:%S.%e volcompd %l: %v");
  }
  spdlog::set_default_logger(std::move(logger));
}

// --probe [--test-offset]: the transport alone; the model is not needed to read a sample or to
// write a test offset through the limiter.
int probe(const std::string& configPath, const volcomp::volcompd::ProbeOptions& options) {
  volcomp::config::DaemonConfig config;
  try {
    config = volcomp::config::loadDaemonConfig(configPath);
    volcomp::volcompd::requireTransportBuiltIn(config.transport, config.file);
    return volcomp::volcompd::runProbe(config, options, std::cout);
  } catch (const volcomp::config::ConfigError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
}

int run(const std::string& configPath, bool checkOnly, bool verbose) {
  volcomp::daemon::LoadedConfiguration loaded;
  std::unique_ptr<volcomp::loop::ControllerPort> port;
  std::string environment;
  try {
    loaded = volcomp::daemon::loadConfiguration(configPath);
    volcomp::volcompd::requireTransportBuiltIn(loaded.config.transport, loaded.config.file);
    port = volcomp::volcompd::makeControllerPort(loaded.config.transport, loaded.config.file);
    if (checkOnly) {
      environment =
          volcomp::volcompd::checkTransportEnvironment(loaded.config.transport, loaded.config.file);
    }
  } catch (const volcomp::config::ConfigError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  spdlog::set_level(verbose ? spdlog::level::debug
                            : spdlog::level::from_str(loaded.config.logLevel));
  if (checkOnly) {
    spdlog::info("{}: configuration, model '{}' and {} transport are valid; {}", configPath,
                 loaded.model->name(), volcomp::config::transportType(loaded.config.transport),
                 environment);
    const auto* modbusSettings =
        std::get_if<volcomp::modbus::ModbusSettings>(&loaded.config.transport);
    const bool stamped = modbusSettings && modbusSettings->registers.timestamp;
    if (loaded.config.latencyCompensation) {
      spdlog::info("latency compensation on: controller latency {} ms; positions sampled {}",
                   loaded.config.controllerLatencyMs,
                   stamped ? "when the timestamp register says"
                           : "at the middle of each read (no timestamp register)");
    } else {
      spdlog::info("latency compensation off{}",
                   stamped ? " (the timestamp register is read but not used)" : "");
    }
    return 0;
  }

  asio::io_context io;
  volcomp::daemon::SteadyWaitableClock clock(io);
  volcomp::daemon::SystemdNotifier notifier;
  asio::signal_set signals(io, SIGINT, SIGTERM, SIGHUP);
  volcomp::daemon::Daemon daemon(
      io, *port, clock, notifier, std::move(loaded),
      [configPath] { return volcomp::daemon::loadConfiguration(configPath); },
      [&] {
        signals.cancel();
        io.stop();
      });

  std::function<void(const std::error_code&, int)> onSignal = [&](const std::error_code& ec,
                                                                  int signal) {
    if (ec) return;
    if (signal == SIGHUP) {
      daemon.requestReload();
    } else {
      daemon.requestStop();
    }
    signals.async_wait(onSignal);
  };
  signals.async_wait(onSignal);
  volcomp::volcompd::connectCycleTrigger(
      *port, [&io, &daemon] { asio::post(io, [&daemon] { daemon.triggerCycle(); }); });
  daemon.start();
  io.run();
  port->disconnect();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A reader of stderr that goes away (journald restarting, a closed pipe) must not kill the
  // daemon with offsets applied: writes then fail with EPIPE, which logging ignores.
  std::signal(SIGPIPE, SIG_IGN);
  setUpLogging();
  const std::string program = volcomp::volcompd::kProgramName;
  CLI::App app{program + ": live volumetric error compensation daemon", program};
  app.set_version_flag("--version", program + " " + VOLCOMP_VERSION);
  std::string configPath;
  bool checkOnly = false;
  bool verbose = false;
  bool probeOnly = false;
  std::string testOffset;
  volcomp::volcompd::ProbeOptions probeOptions;
  app.add_option("-c,--config", configPath, "daemon configuration file (JSON)")->required();
  CLI::Option* check = app.add_flag(
      "--check-config", checkOnly,
      "validate the configuration, the model (plausible, within the limiter) and the transport "
      "(host resolves, device or CAN interface exists), then exit");
  CLI::Option* probeFlag = app.add_flag(
      "--probe", probeOnly,
      "connect, read one consistent sample and print every decoded value with its register or "
      "signal and raw bytes; writes nothing");
  probeFlag->excludes(check);
  app.add_option("--test-offset", testOffset,
                 "with --probe: write one small offset AXIS:VALUE (e.g. X:5um) through the "
                 "limiter, read it back, hold it, ramp it out and report (sign check)")
      ->needs(probeFlag);
  app.add_option("--hold", probeOptions.holdS, "with --test-offset: seconds to hold the offset")
      ->check(CLI::Range(0.0, 600.0));
  app.add_flag("-v,--verbose", verbose, "debug logging (overrides log_level)");
  app.footer(std::string("Exit status: 0 clean stop, good --check-config or --probe; 1 runtime "
                         "failure (or a --test-offset whose read-back disagreed); 2 bad arguments "
                         "or a bad configuration/model file. The configuration's keys: ") +
             volcomp::config::kDaemonConfigKeysListedIn +
             ". Commissioning: docs/commissioning.md.");
  try {
    app.parse(argc, argv);
    if (!testOffset.empty())
      probeOptions.testOffset = volcomp::volcompd::parseTestOffset(testOffset);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  try {
    if (probeOnly) return probe(configPath, probeOptions);
    return run(configPath, checkOnly, verbose);
  } catch (const std::exception& e) {
    spdlog::critical("{}", e.what());
    return 1;
  }
}
