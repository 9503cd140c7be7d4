#pragma once
// Runs the `volcomp` binary under test with arguments, capturing exit status, stdout and stderr.

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_files.hpp"

namespace volcomp::testing {

struct CliRun {
  int status = -1;
  std::string out;
  std::string err;
  /// Number of lines written to stderr.
  int errLines() const {
    int n = 0;
    for (char c : err) n += c == '\n' ? 1 : 0;
    return n;
  }
};

inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// `args` is appended to the command line as is (shell syntax; quote paths with spaces).
inline CliRun runCli(const TempDir& dir, const std::string& args) {
  const std::string out = (dir.path() / "stdout.txt").string();
  const std::string err = (dir.path() / "stderr.txt").string();
  const std::string command =
      std::string("'") + VOLCOMP_CLI + "' " + args + " >'" + out + "' 2>'" + err + "' </dev/null";
  const int raw = std::system(command.c_str());
  CliRun run;
  run.status = raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.out = readFile(out);
  run.err = readFile(err);
  return run;
}

/// Quotes a path for the shell command line of runCli.
inline std::string quoted(const std::string& path) {
  return "'" + path + "'";
}

}  // namespace volcomp::testing
