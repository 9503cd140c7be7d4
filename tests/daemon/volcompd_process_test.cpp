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

#include "temp_dir.hpp"

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

class Child {
 public:
  explicit Child(std::vector<std::string> args) {
    int pipeFds[2];
    if (::pipe2(pipeFds, O_CLOEXEC) != 0) throw std::runtime_error("pipe");
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(pipeFds[1], STDERR_FILENO);
      ::dup2(pipeFds[1], STDOUT_FILENO);
      ::unsetenv("NOTIFY_SOCKET");
      ::unsetenv("JOURNAL_STREAM");
      std::vector<char*> argv;
      for (auto& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(pipeFds[1]);
    fd_ = pipeFds[0];
  }
  ~Child() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    ::close(fd_);
  }

  /// Reads output until a line containing `text` (true) or the timeout / end of output (false).
  bool waitFor(const std::string& text, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (output_.find(text, searched_) == std::string::npos) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          until - std::chrono::steady_clock::now());
      if (left <= 0ms || !readSome(left)) return false;
    }
    searched_ = output_.find(text, searched_) + text.size();
    return true;
  }
  /// Reads to the end of output (the process closed it by exiting) and returns the exit status.
  std::optional<int> waitExit(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          until - std::chrono::steady_clock::now());
      if (left <= 0ms) return std::nullopt;
      if (!readSome(left)) break;
    }
    int status = 0;
    if (::waitpid(pid_, &status, 0) != pid_) return std::nullopt;
    exited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  void signal(int sig) { ::kill(pid_, sig); }
  const std::string& output() const { return output_; }

 private:
  // False at end of output or on timeout.
  bool readSome(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) return false;
    output_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  bool exited_ = false;
  std::string output_;
  std::size_t searched_ = 0;
};

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
  Child run(std::vector<std::string> extra) {
    std::vector<std::string> args{VOLCOMPD_PATH, "--config", configPath_};
    args.insert(args.end(), extra.begin(), extra.end());
    return Child(args);
  }

  TempDir dir_;
  nlohmann::json config_;
  std::string configPath_;
};

TEST_F(VolcompdProcess, CheckConfigAcceptsAGoodFile) {
  Child child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
  EXPECT_NE(child.output().find("valid"), std::string::npos) << child.output();
}

TEST_F(VolcompdProcess, BadFileExitsWithStatus2NamingTheKeyPath) {
  config_["limiter"]["max_rate_mm_s"] = "fast";
  dir_.write("volcompd.json", config_.dump());
  Child child = run({"--check-config"});
  EXPECT_EQ(child.waitExit(20s), 2);
  EXPECT_NE(child.output().find("limiter.max_rate_mm_s"), std::string::npos) << child.output();
}

TEST_F(VolcompdProcess, BadArgumentsExitWithStatus2) {
  Child child = run({"--no-such-option"});
  EXPECT_EQ(child.waitExit(20s), 2);
}

TEST_F(VolcompdProcess, ReloadRejectsABrokenModelAndTermStopsWithStatus0) {
  Child child = run({});
  ASSERT_TRUE(child.waitFor("link lost", 20s)) << child.output();

  const std::string brokenModel = dir_.write("broken.json", R"({"format": "volcomp-model/1",
    "topology": "XYFZ", "components": {"EXX": {"positions": [0, 1], "values": [0]}}})");
  config_["model"] = brokenModel;
  dir_.write("volcompd.json", config_.dump());
  child.signal(SIGHUP);
  ASSERT_TRUE(child.waitFor("reload rejected", 20s)) << child.output();
  EXPECT_NE(child.output().find("components.EXX"), std::string::npos) << child.output();

  child.signal(SIGTERM);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
  EXPECT_NE(child.output().find("stopped"), std::string::npos) << child.output();
}

TEST_F(VolcompdProcess, InterruptStopsWithStatus0) {
  Child child = run({});
  ASSERT_TRUE(child.waitFor("link lost", 20s)) << child.output();
  child.signal(SIGINT);
  EXPECT_EQ(child.waitExit(20s), 0) << child.output();
}

}  // namespace
}  // namespace volcomp::daemon::testing
