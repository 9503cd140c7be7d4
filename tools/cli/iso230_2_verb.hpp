#pragma once
// `volcomp iso230-2`: the ISO 230-2:2014 evaluation of a linear positioning test (bidirectional
// runs from a CSV), a readable table on stdout (um), the full result as JSON, and optionally the
// axis' positioning component as a model file (docs/iso230-2.md).

#include <iosfwd>
#include <optional>
#include <string>

#include <CLI/App.hpp>

#include "volcomp/model/topology.hpp"
#include "volcomp/model/types.hpp"

namespace volcomp::cli {

struct Iso230Options {
  std::string runsPath;
  /// Only this axis' rows (a CSV without an axis column is taken to be of it); none: all rows.
  std::optional<model::Axis> axis;
  std::string jsonPath;
  /// With exactly one of `topology` (a new model) and `mergePath` (the model to copy).
  std::string modelOutPath;
  std::optional<model::Topology> topology;
  std::string mergePath;
};

/// The options as given on the command line; the text ones are resolved after parsing.
struct Iso230Arguments {
  Iso230Options options;
  std::string axis;      ///< X, Y or Z; empty: not given
  std::string topology;  ///< e.g. XYFZ; empty: not given
};

CLI::App* addIso230Verb(CLI::App& app, Iso230Arguments& arguments);

/// Fills arguments.options' axis and topology from the text options, after checking which options
/// go together; throws UsageError naming the option.
void resolveIso230Arguments(Iso230Arguments& arguments);

/// Runs the verb: table to `out`, warnings to `err`. Returns kExitOk; throws config::ConfigError /
/// UsageError for bad files, refused data and bad arguments.
int runIso230(const Iso230Options& options, std::ostream& out, std::ostream& err);

}  // namespace volcomp::cli
