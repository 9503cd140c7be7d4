#pragma once
// `volcomp export`: controller tables from a model (LinuxCNC COMP_FILE per joint, Siemens 840D
// LEC and CEC part programs, a plain CSV of one component), what they carry and cannot carry, and
// the error the model predicts to remain over the travel with only those tables applied, beside
// the uncompensated error and the live compensation's (docs/export.md).

#include <iosfwd>
#include <string>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct ExportOptions {
  std::string modelPath;
  std::string format;
  std::string out;
  std::string step;
  int compType = 1;
  std::string joints = "0,1,2";
  std::string axisNames = "AX1,AX2,AX3";
  int encoder = 0;
  std::string component;
  int checkPoints = 11;
};

CLI::App* addExportVerb(CLI::App& app, ExportOptions& options);

/// Writes the files and prints the summary to `out`. Returns kExitOk; throws config::ConfigError
/// / UsageError for bad files and arguments.
int runExport(const ExportOptions& options, std::ostream& out);

}  // namespace volcomp::cli
