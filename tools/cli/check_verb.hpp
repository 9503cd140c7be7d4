#pragma once
// `volcomp check`: validate a model file and print a summary of what it holds.

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct CheckOptions {
  std::string modelPath;
  bool calibrationTemplate = false;
  /// A daemon configuration whose limiter the model must fit (its max_offset_mm).
  std::string daemonConfig;
  /// Or the limit itself, mm (0 = none).
  double maxOffsetMm = 0.0;
  std::string angleUnit = "urad";
  /// Print the model format's JSON Schema instead of checking a file.
  bool printSchema = false;
};

CLI::App* addCheckVerb(CLI::App& app, CheckOptions& options);

/// Loads and validates the file, checks that the model is plausible over its travel and fits
/// the limiter when one is given (config::ConfigError when not), and prints the summary.
int runCheck(const CheckOptions& options, std::ostream& out);

}  // namespace volcomp::cli
