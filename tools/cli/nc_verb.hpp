#pragma once
// `volcomp nc`: offline compensation of an NC program (RS274/NGC, or the canonical commands of
// LinuxCNC's rs274 -g) with a model; report as JSON and a summary on stderr. Reference:
// docs/nc.md.

#include <iosfwd>
#include <string>
#include <vector>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct NcOptions {
  std::string modelPath;
  std::string inputPath;
  std::string outPath;
  std::string reportPath;
  double toleranceMm = 0.001;
  double checkStepMm = 0.0;
  std::vector<std::string> workOffsets;
  std::string toolTable;
  std::string machineUnits = "mm";
  std::string tool;
  std::string start;
  std::string input = "auto";
  std::string mode = "exact";
  bool quiet = false;
};

CLI::App* addNcVerb(CLI::App& app, NcOptions& options);

/// Runs the verb: the program to options.outPath, the summary (and progress) to `err`. Returns
/// kExitOk or kExitNotConverged; throws nc::NcError, config::ConfigError or UsageError for bad
/// input (nothing is left at options.outPath then).
int runNc(const NcOptions& options, std::ostream& err);

}  // namespace volcomp::cli
