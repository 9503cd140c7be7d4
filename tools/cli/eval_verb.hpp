#pragma once
// `volcomp eval`: the error, angular error and compensation offset of a model at one point
// (--at) or for a CSV file of points (--points/--out). Contract: docs/model-file.md, "volcomp
// eval".

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct EvalOptions {
  std::string modelPath;
  std::string at;
  std::string tool;
  std::string direction;
  std::string points;
  std::string out;
  std::string mode = "exact";
  bool json = false;
  std::string angleUnit = "urad";  ///< on screen: urad or arcsec (JSON and CSV: rad)
};

/// Registers the verb and its options (bound to `options`) on `app`.
CLI::App* addEvalVerb(CLI::App& app, EvalOptions& options);

/// Runs the verb: results to `out`, warnings to `err`. Returns the exit status (kExitOk or
/// kExitNotConverged); throws config::ConfigError / UsageError for bad files and arguments.
int runEval(const EvalOptions& options, std::ostream& out, std::ostream& err);

}  // namespace volcomp::cli
