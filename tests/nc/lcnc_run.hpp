#pragma once
// Running the programs of the LinuxCNC checks: `volcomp nc`, LinuxCNC's standalone interpreter
// rs274 (Debian package linuxcnc-uspace) and lcnc_canon.py (the same interpreter through its
// Python binding, at full precision). rs274 needs no LinuxCNC lock (it is not LinuxCNC running).

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "../cli/run_cli.hpp"
#include "temp_files.hpp"

namespace volcomp::testing {

struct Command {
  int status = -1;
  std::string out;
  std::string err;
};

/// Runs a shell command line in `dir` with stdin from /dev/null; stdout and stderr captured.
inline Command runCommand(const TempDir& dir, const std::string& commandLine) {
  const std::string out = (dir.path() / "cmd-stdout.txt").string();
  const std::string err = (dir.path() / "cmd-stderr.txt").string();
  const std::string command = "cd " + quoted(dir.path().string()) + " && " + commandLine + " >" +
                              quoted(out) + " 2>" + quoted(err) + " </dev/null";
  const int raw = std::system(command.c_str());
  Command c;
  c.status = raw != -1 && WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  c.out = readFile(out);
  c.err = readFile(err);
  return c;
}

/// LinuxCNC's rs274 -g on `program` with a tool table and a copy of the parameter file (rs274
/// writes its parameters back at the end). Inch machine units, as rs274 has them.
inline Command rs274(const TempDir& dir, const std::string& program, const std::string& varFile,
                     const std::string& toolTable) {
  const std::filesystem::path copy = dir.path() / "rs274-parameters.var";
  std::filesystem::copy_file(varFile, copy, std::filesystem::copy_options::overwrite_existing);
  // rs274 keeps its tool table in $HOME/.tool.mmap; two at once on one file die of SIGBUS when
  // one truncates it under the other, so each test gives rs274 a home of its own.
  std::string line = "HOME=" + quoted(dir.path().string()) + " rs274 -g";
  if (!toolTable.empty()) line += " -t " + quoted(toolTable);
  line += " -v " + quoted(copy.string()) + " " + quoted(program);
  return runCommand(dir, line);
}

/// The same interpreter at full precision (lcnc_canon.py; no tool changes there).
inline Command linuxCncFullPrecision(const TempDir& dir, const std::string& program,
                                     const std::string& varFile) {
  const std::filesystem::path copy = dir.path() / "python-parameters.var";
  std::filesystem::copy_file(varFile, copy, std::filesystem::copy_options::overwrite_existing);
  return runCommand(dir, quoted(VOLCOMP_PYTHON) + " " + quoted(VOLCOMP_LCNC_CANON) + " " +
                             quoted(program) + " " + quoted(copy.string()));
}

}  // namespace volcomp::testing
