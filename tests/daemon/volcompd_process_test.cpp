// volcompd as a process: --check-config, a bad file (exit 2 naming the key path), SIGHUP with a
// broken model (rejected, keeps running), SIGTERM (exit 0). The controller address is a loopback
// port chosen at run time on which nothing listens, so the daemon sits in "link lost"; output is
// read through a pipe with poll() timeouts, never by sleeping.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "subprocess.hpp"
#include "temp_files.hpp"

namespace volcomp::daemon::testing {
namespace {

using namespace std::chrono_literals;

// A loopback TCP port nothing listens on: bound, then released.
int unusedPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t len = sizeof addr;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  ::close(fd);
  return ntohs(addr.sin_port);
}

class VolcompdProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = nlohmann::json::parse(R"({
      "cycle_period_ms": 10, "position_semantics": "commanded",
      "limiter": {"max_offset_mm": 0.1, "max_rate_mm_s": 0.5},
      "reconnect": {"initial_ms": 20, "max_ms": 50},
      "transport": {"type": "modbus-tcp", "host": "127.0.0.1", "response_timeout_ms": 50,
        "registers": {
          "defaults": {"type": "int32", "counts_per_mm": 10000},
          "position": {"X": {"address": 0}, "Y": {"address": 2}, "Z": {"address": 4}},
          "enable": {"address": 6, "bit": 0}, "homed": {"address": 6, "bit": 1},
          "applied_offset": {"X": {"address": 8}, "Y": {"address": 10}, "Z": {"address": 12}},
          "offset": {"X": {"address": 8}, "Y": {"address": 10}, "Z": {"address": 12}},
          "status": 14, "heartbeat": 15}}
    })");
    config_["model"] = std::string(VOLCOMP_EXAMPLES_DIR) + "/vmc-xyfz-21.json";
    config_["transport"]["port"] = unusedPort();
    configPath_ = dir_.write("volcompd.json", config_.dump(2));
  }
  testutil::Subprocess run(std::vector<std::string> extra) {
    std::vector<std::string> args{VOLCOMPD_PATH, "--config", configPath_};
    args.insert(args.end(), extra.begin(), extra.end());
    // stderr onto the stdout pipe (the log and the messages in one text); not under systemd.
    return testutil::Subprocess(args, "", {"NOTIFY_SOCKET", "JOURNAL_STREAM"});
  }

  volcomp::testing::TempDir dir_;
  nlohmann::json config_;
  std::string configPath_;
};

TEST_F(VolcompdProcess, CheckConfigAcceptsAGoodFile) {
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
  EXPECT_NE(child.output().find("valid"), std::string::npos) << child.output();
}

// What --check-config says about latency compensation: where the sample time comes from.
TEST_F(VolcompdProcess, CheckConfigSaysWhereTheSampleTimeComesFrom) {
  config_["latency_compensation"] = {{"enabled", true}, {"controller_latency_ms", 2}};
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess plain = run({"--check-config"});
  EXPECT_EQ(plain.waitExit(20s), 0) << plain.output();
  EXPECT_NE(plain.output().find("latency compensation on: controller latency 2 ms; positions "
                                "sampled at the middle of each read (no timestamp register)"),
            std::string::npos)
      << plain.output();
  config_["transport"]["registers"]["timestamp"] = {{"address", 16}, {"tick_us", 10}};
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess stamped = run({"--check-config"});
  EXPECT_EQ(stamped.waitExit(20s), 0) << stamped.output();
  EXPECT_NE(stamped.output().find("positions sampled when the timestamp register says"),
            std::string::npos)
      << stamped.output();
  config_["latency_compensation"]["enabled"] = false;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess unused = run({"--check-config"});
  EXPECT_EQ(unused.waitExit(20s), 0) << unused.output();
  EXPECT_NE(unused.output().find(
                "latency compensation off (the timestamp register is read but not used)"),
            std::string::npos)
      << unused.output();
}

TEST_F(VolcompdProcess, BadFileExitsWithStatus2NamingTheKeyPath) {
  config_["limiter"]["max_rate_mm_s"] = "fast";
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  EXPECT_NE(child.output().find("limiter.max_rate_mm_s"), std::string::npos) << child.output();
}

// A key misspelt among the twenty of the file: one line naming the file, the key, the key it
// most likely meant and where the keys are listed; --help says where too.
TEST_F(VolcompdProcess, AnUnknownKeyIsOneShortLineAndHelpSaysWhereTheKeysAre) {
  config_["cycle_perod_ms"] = 10;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  const std::string out = child.output();
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  EXPECT_NE(out.find(configPath_ + ": cycle_perod_ms: unknown key; did you mean "
                                   "\"cycle_period_ms\"? (the 20 keys allowed here: "
                                   "docs/daemon.md, Configuration reference)"),
            std::string::npos)
      << out;
  EXPECT_LE(out.size(), 300u) << out;
  testutil::Subprocess help = run({"--help"});
  EXPECT_EQ(help.waitExit(20s), 0);
  EXPECT_NE(help.output().find("The configuration's keys: docs/daemon.md, Configuration "
                               "reference."),
            std::string::npos)
      << help.output();
}

TEST_F(VolcompdProcess, BadArgumentsExitWithStatus2) {
  testutil::Subprocess child = run({"--no-such-option"});
  EXPECT_EQ(child.waitExit(20s), 2);
}

TEST_F(VolcompdProcess, ReloadRejectsABrokenModelAndTermStopsWithStatus0) {
  testutil::Subprocess child = run({});
  ASSERT_TRUE(child.waitForOutput("link lost", 20s)) << child.output();

  const std::string brokenModel = dir_.write("broken.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "components": {"EXX": {"positions": [0, 1], "values": [0]}}})");
  config_["model"] = brokenModel;
  dir_.write("volcompd.json", config_.dump());
  child.signal(SIGHUP);
  ASSERT_TRUE(child.waitForOutput("reload rejected", 20s)) << child.output();
  EXPECT_NE(child.output().find("components.EXX"), std::string::npos) << child.output();

  child.signal(SIGTERM);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
  EXPECT_NE(child.output().find("stopped"), std::string::npos) << child.output();
}

// A model that evaluates to infinity inside its travel is rejected by a reload like any invalid
// file: the running model stays.
TEST_F(VolcompdProcess, ReloadRejectsAModelThatEvaluatesToInfinity) {
  testutil::Subprocess child = run({});
  ASSERT_TRUE(child.waitForOutput("link lost", 20s)) << child.output();
  const std::string infinite = dir_.write("infinite.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "travel": {"X": [0, 850]}, "error_units": {"length": "um", "angle": "urad"},
    "components": {"EXX": {"polynomial": [0, 0, 0, 0, 1e300]}}})");
  config_["model"] = infinite;
  dir_.write("volcompd.json", config_.dump());
  child.signal(SIGHUP);
  ASSERT_TRUE(child.waitForOutput("reload rejected", 20s)) << child.output();
  EXPECT_NE(child.output().find("not finite"), std::string::npos) << child.output();
  // --check-config refuses it as well.
  testutil::Subprocess check = run({"--check-config"});
  EXPECT_EQ(check.waitExit(20s), 2) << check.output();
  EXPECT_NE(check.output().find("components.EXX"), std::string::npos) << check.output();
  child.signal(SIGTERM);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
}

// An offset register that cannot hold max_offset: an int16 at 10^6 counts/mm holds +-0.033 mm.
TEST_F(VolcompdProcess, CheckConfigRefusesAnOffsetRegisterThatCannotHoldMaxOffset) {
  config_["transport"]["registers"]["offset"]["Z"] = {
      {"address", 12}, {"type", "int16"}, {"counts_per_mm", 1000000}};
  config_["transport"]["registers"]["applied_offset"]["Z"] = {
      {"address", 12}, {"type", "int16"}, {"counts_per_mm", 1000000}};
  config_["transport"]["registers"]["status"] = 13;
  config_["transport"]["registers"]["heartbeat"] = 14;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2) << child.output();
  EXPECT_NE(child.output().find("transport.registers.offset.Z"), std::string::npos)
      << child.output();
  EXPECT_NE(child.output().find("holds +-0.032767 mm"), std::string::npos) << child.output();
}

// A response timeout with which a silent controller holds a cycle longer than the unit's watchdog
// allows (one read and one write of 600 ms > half of WatchdogSec=2s).
TEST_F(VolcompdProcess, CheckConfigRefusesAResponseTimeoutTheWatchdogDoesNotAllow) {
  config_["transport"]["response_timeout_ms"] = 600;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2) << child.output();
  EXPECT_NE(child.output().find("transport.response_timeout_ms"), std::string::npos)
      << child.output();
  EXPECT_NE(child.output().find("watchdog"), std::string::npos) << child.output();
}

// The reader of the daemon's stderr goes away (here: the test closes the pipe): the next log line
// fails with EPIPE, and the daemon neither dies of SIGPIPE nor stops working; SIGTERM still ends
// it with status 0.
TEST_F(VolcompdProcess, SurvivesTheReaderOfItsLogGoingAway) {
  testutil::Subprocess child = run({});
  ASSERT_TRUE(child.waitForOutput("link lost", 20s)) << child.output();
  child.closeStdout();
  child.signal(SIGHUP);  // logs "reloading ..." into the closed pipe
  child.signal(SIGTERM);
  EXPECT_EQ(child.waitExit(20s), 0);
}

TEST_F(VolcompdProcess, InterruptStopsWithStatus0) {
  testutil::Subprocess child = run({});
  ASSERT_TRUE(child.waitForOutput("link lost", 20s)) << child.output();
  child.signal(SIGINT);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
}

// The model of the example machine with its positioning error in um but "length": "mm": 1000
// times too large. --check-config refuses it in one line, before it ever reaches a machine.
constexpr const char* kTypedAsMm = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "mm", "angle": "urad"},
  "components": {"EXX": {"positions": [0, 425, 850], "values": [0, 8.7, 15.6]}}})";

TEST_F(VolcompdProcess, CheckConfigRefusesMicrometresTypedAsMillimetres) {
  config_["model"] = dir_.write("mm.json", kTypedAsMm);
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  const std::string out = child.output();
  EXPECT_NE(out.find("mm.json: components.EXX"), std::string::npos) << out;
  EXPECT_NE(out.find("Were values in um entered as mm?"), std::string::npos) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST_F(VolcompdProcess, CheckConfigRefusesAModelWhoseOffsetsExceedTheLimiter) {
  config_["limiter"]["max_offset_mm"] = 0.01;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  EXPECT_NE(child.output().find("the model asks for an offset of"), std::string::npos)
      << child.output();
  EXPECT_NE(child.output().find("limiter.max_offset_mm of"), std::string::npos) << child.output();
}

TEST_F(VolcompdProcess, CheckConfigRefusesAHostThatDoesNotResolve) {
  config_["transport"]["host"] = "no-such-controller.invalid";
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  EXPECT_NE(child.output().find("transport.host: \"no-such-controller.invalid\" does not resolve"),
            std::string::npos)
      << child.output();
}

TEST_F(VolcompdProcess, CheckConfigSaysHowToCreateAMissingCanInterface) {
  nlohmann::json can = nlohmann::json::parse(
      std::ifstream(std::string(VOLCOMP_EXAMPLES_DIR) + "/volcompd-can.json"));
  can["model"] = config_["model"];
  can["transport"]["dbc"] = std::string(VOLCOMP_EXAMPLES_DIR) + "/vmc-can.dbc";
  can["transport"]["interface"] = "vcan97";
  dir_.write("volcompd.json", can.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  const std::string out = child.output();
  EXPECT_NE(out.find("the CAN interface vcan97 does not exist"), std::string::npos) << out;
  EXPECT_NE(out.find("sudo ip link add dev vcan97 type vcan"), std::string::npos) << out;
}

TEST_F(VolcompdProcess, CheckConfigReportsWhatItFound) {
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
  EXPECT_NE(child.output().find("host 127.0.0.1 resolves to 127.0.0.1"), std::string::npos)
      << child.output();
}

TEST_F(VolcompdProcess, MaxOffsetAbove2mmNeedsAnExplicitOverride) {
  config_["limiter"]["max_offset_mm"] = 3.0;
  config_["limiter"]["max_rate_mm_s"] = 2.0;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess refused = run({"--check-config"});
  EXPECT_EQ(refused.waitExit(20s), 2);
  EXPECT_NE(refused.output().find("limiter.max_offset_mm"), std::string::npos) << refused.output();
  EXPECT_NE(refused.output().find("allow_max_offset_above_2mm"), std::string::npos)
      << refused.output();
  config_["limiter"]["allow_max_offset_above_2mm"] = true;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess accepted = run({"--check-config"});
  EXPECT_EQ(accepted.waitExit(20s), 0) << accepted.output();
}

TEST_F(VolcompdProcess, TheRampOutMustFitTheUnitsStopTimeout) {
  // 0.1 mm at 0.01 mm/s: a 10 s ramp-out, a stop of up to 21 s, beyond TimeoutStopSec=15s.
  config_["limiter"]["max_rate_mm_s"] = 0.01;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess refused = run({"--check-config"});
  EXPECT_EQ(refused.waitExit(20s), 2);
  const std::string out = refused.output();
  EXPECT_NE(out.find("limiter: the ramp-out takes up to 10 s"), std::string::npos) << out;
  EXPECT_NE(out.find("TimeoutStopSec"), std::string::npos) << out;
  config_["stop_timeout_s"] = 30;
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess accepted = run({"--check-config"});
  EXPECT_EQ(accepted.waitExit(20s), 0) << accepted.output();
}

// The LinuxCNC transport is volcompd-linuxcnc's: plain volcompd reads the section, then refuses it
// in one line naming the program and the package that have it, like any bad configuration.
TEST_F(VolcompdProcess, RefusesTheLinuxCncTransportNamingVolcompdLinuxcnc) {
  config_["transport"] = nlohmann::json::parse(R"({"type": "linuxcnc", "component": "volcomp"})");
  dir_.write("volcompd.json", config_.dump());
  for (const char* mode : {"--check-config", "--probe"}) {
    testutil::Subprocess child = run({mode});
    EXPECT_EQ(child.waitExit(20s), 2) << mode << ": " << child.output();
    const std::string out = child.output();
    EXPECT_NE(out.find("transport.type: \"linuxcnc\" is the transport of volcompd-linuxcnc "
                       "(package volcomp-linuxcnc)"),
              std::string::npos)
        << mode << ": " << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << mode << ": " << out;
  }
}

TEST_F(VolcompdProcess, PrintsItsVersion) {
  testutil::Subprocess child = testutil::Subprocess({VOLCOMPD_PATH, "--version"}, "");
  EXPECT_EQ(child.waitExit(20s), 0);
  EXPECT_EQ(child.output(), std::string("volcompd ") + VOLCOMP_VERSION + "\n");
}

// A reload runs the same check: an implausible model is rejected and the running one stays.
TEST_F(VolcompdProcess, ReloadRejectsAnImplausibleModel) {
  testutil::Subprocess child = run({});
  ASSERT_TRUE(child.waitForOutput("link lost", 20s)) << child.output();
  EXPECT_NE(child.output().find("starting volcompd " + std::string(VOLCOMP_VERSION)),
            std::string::npos)
      << child.output();
  EXPECT_NE(child.output().find("link lost to modbus-tcp 127.0.0.1:"), std::string::npos)
      << child.output();
  config_["model"] = dir_.write("mm.json", kTypedAsMm);
  dir_.write("volcompd.json", config_.dump());
  child.signal(SIGHUP);
  ASSERT_TRUE(child.waitForOutput("reload rejected", 20s)) << child.output();
  EXPECT_NE(child.output().find("Were values in um entered as mm?"), std::string::npos)
      << child.output();
  child.signal(SIGTERM);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
}

}  // namespace
}  // namespace volcomp::daemon::testing
