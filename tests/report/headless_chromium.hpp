#pragma once
// Headless Chromium driven over the DevTools protocol on a pipe (--remote-debugging-pipe: the
// browser reads commands on fd 3 and writes replies and events on fd 4, each a JSON text ended by
// a NUL byte). No WebSocket and no fixed port: the pipe belongs to this process only. Every
// event is kept, so that a test can check the console and the network afterwards. Waiting is on
// poll() with a deadline, never a sleep.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "wait_until.hpp"

extern char** environ;

namespace volcomp::testutil {

class HeadlessChromium {
 public:
  using Json = nlohmann::json;

  /// Starts `browser` (e.g. /usr/bin/chromium) with a fresh profile in `profileDir`; its own
  /// output goes to `logFile`. Attaches to its first page.
  HeadlessChromium(const std::string& browser, const std::string& profileDir,
                   const std::string& logFile) {
    ::signal(SIGPIPE, SIG_IGN);  // a browser that died must fail a write, not end the test
    int commands[2], replies[2];
    if (::pipe2(commands, O_CLOEXEC) != 0 || ::pipe2(replies, O_CLOEXEC) != 0) {
      throw std::runtime_error("pipe2 failed");
    }
    // Above fd 4, so that dup2 onto 3 and 4 never meets the same descriptor.
    const int browserReads = ::fcntl(commands[0], F_DUPFD_CLOEXEC, 10);
    const int browserWrites = ::fcntl(replies[1], F_DUPFD_CLOEXEC, 10);
    ::close(commands[0]);
    ::close(replies[1]);
    toBrowser_ = commands[1];
    fromBrowser_ = replies[0];

    const std::vector<std::string> argv{
        browser, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--disable-extensions", "--mute-audio", "--hide-scrollbars",
        // No name resolves and no proxy answers: the page must
        // need nothing but itself.
        "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9",
        "--user-data-dir=" + profileDir, "--remote-debugging-pipe", "about:blank"};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, logFile.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    posix_spawn_file_actions_adddup2(&actions, browserReads, 3);
    posix_spawn_file_actions_adddup2(&actions, browserWrites, 4);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const int rc = ::posix_spawn(&pid_, argv[0].c_str(), &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(browserReads);
    ::close(browserWrites);
    if (rc != 0) {
      pid_ = -1;
      throw std::runtime_error("cannot start " + browser + ": " + std::strerror(rc));
    }
    const Json targets = browserCall("Target.getTargets");
    std::string page;
    for (const Json& t : targets["targetInfos"]) {
      if (t["type"] == "page") page = t["targetId"];
    }
    if (page.empty()) throw std::runtime_error("Chromium has no page target");
    session_ =
        browserCall("Target.attachToTarget", {{"targetId", page}, {"flatten", true}})["sessionId"]
            .get<std::string>();
  }

  ~HeadlessChromium() {
    if (pid_ > 0) {
      try {
        send("Browser.close", Json::object(), false);
      } catch (const std::exception&) {
      }
      const bool exited = waitUntil(
          [&] {
            int status = 0;
            return ::waitpid(pid_, &status, WNOHANG) == pid_;
          },
          std::chrono::seconds(10));
      if (!exited) {
        ::kill(pid_, SIGKILL);
        int status = 0;
        ::waitpid(pid_, &status, 0);
      }
    }
    ::close(toBrowser_);
    ::close(fromBrowser_);
  }
  HeadlessChromium(const HeadlessChromium&) = delete;
  HeadlessChromium& operator=(const HeadlessChromium&) = delete;

  /// A command to the attached page; returns its "result" or throws with the protocol's error.
  Json call(const std::string& method, const Json& params = Json::object(),
            std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
    return await(send(method, params, true), timeout);
  }

  /// A command to the browser itself.
  Json browserCall(const std::string& method, const Json& params = Json::object(),
                   std::chrono::milliseconds timeout = std::chrono::seconds(60)) {
    return await(send(method, params, false), timeout);
  }

  /// Waits for the first event `method` at or after position `from` of events() (take
  /// events().size() before the command that causes it).
  Json awaitEvent(const std::string& method, std::size_t from, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (std::size_t i = from;; ++i) {
      while (i >= events_.size()) handle(receive(deadline));
      if (events_[i]["method"] == method) return events_[i];
    }
  }

  /// The value of a JavaScript expression in the page (awaited when it is a promise).
  Json evaluate(const std::string& expression, bool awaitPromise = false) {
    const Json result =
        call("Runtime.evaluate",
             {{"expression", expression}, {"returnByValue", true}, {"awaitPromise", awaitPromise}});
    if (result.contains("exceptionDetails")) {
      throw std::runtime_error("JavaScript error: " + result["exceptionDetails"].dump());
    }
    return result["result"].value("value", Json());
  }

  /// Every event received so far (console, exceptions, network, page life cycle).
  const std::vector<Json>& events() const noexcept { return events_; }

 private:
  int send(const std::string& method, const Json& params, bool toPage) {
    Json message{{"id", ++lastId_}, {"method", method}, {"params", params}};
    if (toPage) message["sessionId"] = session_;
    std::string text = message.dump();
    text.push_back('\0');
    for (std::size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(toBrowser_, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw std::runtime_error("Chromium closed its command pipe");
      done += static_cast<std::size_t>(n);
    }
    return lastId_;
  }

  Json await(int id, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      Json message = receive(deadline);
      if (message.contains("id") && message["id"] == id) {
        if (message.contains("error")) {
          throw std::runtime_error("DevTools error: " + message["error"].dump());
        }
        return message["result"];
      }
      handle(std::move(message));
    }
  }

  void handle(Json message) {
    if (message.contains("method")) events_.push_back(std::move(message));
  }

  Json receive(std::chrono::steady_clock::time_point deadline) {
    for (;;) {
      const auto end = buffer_.find('\0');
      if (end != std::string::npos) {
        Json message = Json::parse(buffer_.substr(0, end));
        buffer_.erase(0, end + 1);
        return message;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) throw std::runtime_error("no answer from Chromium in time");
      pollfd fd{fromBrowser_, POLLIN, 0};
      const int ready = ::poll(&fd, 1, static_cast<int>(left.count()));
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) continue;
      char chunk[65536];
      const ssize_t n = ::read(fromBrowser_, chunk, sizeof chunk);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw std::runtime_error("Chromium closed its reply pipe");
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  pid_t pid_ = -1;
  int toBrowser_ = -1;
  int fromBrowser_ = -1;
  int lastId_ = 0;
  std::string session_;
  std::string buffer_;
  std::vector<Json> events_;
};

/// Standard base64 (RFC 4648) to bytes; for screenshots.
inline std::string decodeBase64(const std::string& text) {
  static const std::string alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const auto value = alphabet.find(c);
    if (value == std::string::npos) continue;
    buffer = (buffer << 6) | static_cast<unsigned>(value);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

}  // namespace volcomp::testutil
