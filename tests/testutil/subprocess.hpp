#pragma once
// A child process for tests: started with posix_spawn with stdin and stdout on pipes and stderr
// to a file (or onto the stdout pipe), environment variables added or removed, lines or text read
// from stdout with a deadline (poll, never a sleep), signals sent by pid, exit awaited with a
// deadline. The destructor kills
// and reaps a child that is still running, so a failing test leaves no process behind.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "wait_until.hpp"

extern char** environ;

namespace volcomp::testutil {

/// The whole content of a text file ("" when it does not exist).
inline std::string readTextFile(const std::string& file) {
  std::ifstream in(file);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class Subprocess {
 public:
  /// Starts argv[0] (a path) with the arguments and the parent's environment changed by
  /// `extraEnv`: "NAME=value" entries override the parent's, a bare "NAME" removes it. stderr goes
  /// to `stderrFile`, or onto the stdout pipe when `stderrFile` is empty.
  explicit Subprocess(const std::vector<std::string>& argv,
                      const std::string& stderrFile = "/dev/null",
                      const std::vector<std::string>& extraEnv = {})
      : stderrFile_(stderrFile) {
    int in[2], out[2];
    if (::pipe2(in, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
    if (::pipe2(out, O_CLOEXEC) != 0) {
      ::close(in[0]);
      ::close(in[1]);
      throw std::runtime_error("pipe2 failed");
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    if (stderrFile.empty()) {
      posix_spawn_file_actions_adddup2(&actions, out[1], STDERR_FILENO);
    } else {
      posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, stderrFile.c_str(),
                                       O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::vector<std::string> env;
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry(*e);
      const std::string name = entry.substr(0, entry.find('='));
      bool overridden = false;
      for (const auto& x : extraEnv) {
        overridden = overridden || x == name || x.rfind(name + "=", 0) == 0;
      }
      if (!overridden) env.push_back(entry);
    }
    for (const auto& x : extraEnv) {
      if (x.find('=') != std::string::npos) env.push_back(x);
    }
    std::vector<char*> envp;
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    const int rc = ::posix_spawn(&pid_, args[0], &actions, nullptr, args.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    ::close(in[0]);
    ::close(out[1]);
    stdin_ = in[1];
    stdout_ = out[0];
    if (rc != 0) {
      pid_ = -1;
      ::close(stdin_);
      ::close(stdout_);
      throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
    }
  }

  ~Subprocess() {
    if (pid_ > 0 && !exited_) {
      ::kill(pid_, SIGKILL);
      int st = 0;
      ::waitpid(pid_, &st, 0);
    }
    ::close(stdin_);
    ::close(stdout_);
  }
  Subprocess(const Subprocess&) = delete;
  Subprocess& operator=(const Subprocess&) = delete;

  pid_t pid() const noexcept { return pid_; }
  /// Closes the reading end of the child's stdout pipe: the child's next write there fails with
  /// EPIPE (and raises SIGPIPE, unless it ignores it).
  void closeStdout() noexcept {
    ::close(stdout_);
    stdout_ = -1;
    eof_ = true;
  }

  /// The next line of stdout, or nullopt when none arrives before the timeout or at EOF.
  std::optional<std::string> readLine(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto nl = buffer_.find('\n');
      if (nl != std::string::npos) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return line;
      }
      if (eof_) return std::nullopt;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      readChunk(left);
    }
  }

  /// Reads stdout until `text` appears after the end of the previous match (true), or the
  /// timeout expires or stdout ends (false). Lines it reads stay available to readLine.
  bool waitForOutput(const std::string& text, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto found = output_.find(text, searched_);
      if (found != std::string::npos) {
        searched_ = found + text.size();
        return true;
      }
      if (eof_) return false;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      readChunk(left);
    }
  }

  /// Everything the child has written on stdout so far (what is already in the pipe included).
  const std::string& output() {
    while (!eof_ && readChunk(std::chrono::milliseconds(0))) {
    }
    return output_;
  }

  /// Reads lines until one satisfies `match` (returned) or the timeout expires (nullopt).
  std::optional<std::string> readLineMatching(const std::function<bool(const std::string&)>& match,
                                              std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      auto line = readLine(left);
      if (!line) return std::nullopt;
      if (match(*line)) return line;
    }
  }

  /// Writes one line to the child's stdin.
  void writeLine(const std::string& line) {
    const std::string s = line + "\n";
    if (::write(stdin_, s.data(), s.size()) != static_cast<ssize_t>(s.size())) {
      throw std::runtime_error("cannot write to the child's stdin");
    }
  }

  void signal(int sig) const {
    if (pid_ > 0 && !exited_) ::kill(pid_, sig);
  }

  /// Whether the child is still running (reaps it when it has exited).
  bool running() {
    if (exited_) return false;
    int st = 0;
    if (::waitpid(pid_, &st, WNOHANG) == pid_) {
      exited_ = true;
      status_ = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    }
    return !exited_;
  }

  /// The exit status once the child has exited within the timeout: its exit code, or 128 + the
  /// signal that killed it; -1 if it is still running at the deadline. stdout is read meanwhile
  /// (kept for readLine and output()), so a child with a lot to say cannot block on a full pipe.
  int waitExit(std::chrono::milliseconds timeout) {
    const auto drainedAndExited = [this] {
      while (!eof_ && readChunk(std::chrono::milliseconds(0))) {
      }
      return !running();
    };
    if (!waitUntil(drainedAndExited, timeout)) return -1;
    return status_;
  }

  /// What the child wrote on stderr so far.
  std::string stderrText() const { return readTextFile(stderrFile_); }

  /// Waits until the child's stderr contains `text`.
  bool waitForStderr(const std::string& text, std::chrono::milliseconds timeout) const {
    return waitUntil([&] { return stderrText().find(text) != std::string::npos; }, timeout);
  }

 private:
  // Waits up to `timeout` for stdout and appends one read to the line buffer and the transcript;
  // false when nothing was read (timeout or end of stdout, which sets eof_).
  bool readChunk(std::chrono::milliseconds timeout) {
    pollfd p{stdout_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    char chunk[4096];
    const ssize_t n = ::read(stdout_, chunk, sizeof chunk);
    if (n <= 0) {
      eof_ = true;
      return false;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
    output_.append(chunk, static_cast<std::size_t>(n));
    return true;
  }

  std::string stderrFile_;
  pid_t pid_ = -1;
  int stdin_ = -1;
  int stdout_ = -1;
  bool exited_ = false;
  bool eof_ = false;
  int status_ = -1;
  std::string buffer_;
  std::string output_;
  std::size_t searched_ = 0;
};

}  // namespace volcomp::testutil
