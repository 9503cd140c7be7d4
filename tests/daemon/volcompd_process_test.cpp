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

TEST_F(VolcompdProcess, BadFileExitsWithStatus2NamingTheKeyPath) {
  config_["limiter"]["max_rate_mm_s"] = "fast";
  dir_.write("volcompd.json", config_.dump());
  testutil::Subprocess child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  EXPECT_NE(child.output().find("limiter.max_rate_mm_s"), std::string::npos) << child.output();
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

}  // namespace
}  // namespace volcomp::daemon::testing
