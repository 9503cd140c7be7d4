#pragma once
// `volcomp iso230-2`: the ISO 230-2:2014 evaluation of a linear positioning test (bidirectional
// runs from a CSV), a readable table on stdout (um), the full result as JSON, and optionally the
// axis' positioning component as a model file (docs/iso230-2.md).

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct Iso230Options {
  std::string runsPath;
  std::string axis;
  std::string jsonPath;
  std::string modelOutPath;
  std::string topology;
  std::string mergePath;
};

CLI::App* addIso230Verb(CLI::App& app, Iso230Options& options);

/// Runs the verb: table to `out`, warnings to `err`. Returns kExitOk; throws config::ConfigError /
/// UsageError for bad files, refused data and bad arguments.
int runIso230(const Iso230Options& options, std::ostream& out, std::ostream& err);

}  // namespace volcomp::cli
