#pragma once
// `volcomp check`: validate a model file and print a summary of what it holds.

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct CheckOptions {
  std::string modelPath;
  bool calibrationTemplate = false;
};

CLI::App* addCheckVerb(CLI::App& app, CheckOptions& options);

/// Loads and validates the file (config::ConfigError when invalid) and prints the summary.
int runCheck(const CheckOptions& options, std::ostream& out);

}  // namespace volcomp::cli
