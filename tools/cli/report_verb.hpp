#pragma once
// `volcomp report`: one self-contained HTML report from a model and, where given, a calibration
// report, an ISO 230-2 result and a compensation run (docs/report.md).

#include <iosfwd>
#include <string>
#include <vector>

#include <CLI/App.hpp>

namespace volcomp::cli {

struct ReportOptions {
  std::string modelPath;
  std::string outPath;
  std::string calibrationPath;
  std::string measurementsPath;       ///< default: the calibration report's "measurements"
  std::string templatePath;           ///< default: the calibration report's "template"
  std::vector<std::string> isoPaths;  ///< one ISO 230-2 evaluation per axis
  std::string runPath;
  std::string writesPath;
  std::string title = "Machine accuracy report";
  std::string machine;
  std::string zLevels;
  int mapCells = 24;
};

CLI::App* addReportVerb(CLI::App& app, ReportOptions& options);

/// Writes the report; one line to `out` with its path, size and sections; what could not be
/// shown to `err` ("note: ..."). Throws config::ConfigError / UsageError for bad files and
/// arguments.
int runReport(const ReportOptions& options, std::ostream& out, std::ostream& err);

}  // namespace volcomp::cli
