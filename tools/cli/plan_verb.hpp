#pragma once
// `volcomp plan TEMPLATE.json (--candidates C.csv | --grid NX,NY,NZ) --points N [--tools
// "TX,TY,TZ;..."] [--noise MM] [--criterion d|i] [--out PLAN.csv] [--report PLAN.json]`: the
// options, the candidates read, volcomp::calibration::planMeasurements, the expected
// uncertainties printed and the plan written.

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include <CLI/App.hpp>
#include <Eigen/Core>

#include "volcomp/calibration/planning.hpp"
#include "volcomp/calibration/report.hpp"

namespace volcomp::cli {

struct PlanVerbOptions {
  std::string templatePath;
  /// CSV x,y,z [,tx,ty,tz] [,direction]; without tool columns every candidate is taken with
  /// every tool of `toolsMm`.
  std::string candidatesPath;
  /// Grid nodes per axis over the template's travel (used when candidatesPath is empty).
  std::array<int, 3> grid{0, 0, 0};
  /// Tool offsets (mm); empty: the template's tool.
  std::vector<Eigen::Vector3d> toolsMm;
  /// points, criterion, noiseMm, rankTolerance (progress is set by runPlan).
  calibration::PlanOptions plan;
  std::string outPath;     ///< the chosen points as CSV x,y,z,tx,ty,tz [,direction]
  std::string reportPath;  ///< JSON report
  calibration::AngleDisplay angleDisplay = calibration::AngleDisplay::Microradian;
  /// Where the progress lines of the exchanges go (the CLI: stderr); null: into `out`.
  std::ostream* progress = nullptr;
};

/// The options as given on the command line; the text ones are resolved after parsing.
struct PlanArguments {
  PlanVerbOptions options;
  std::string grid;   ///< "NX,NY,NZ"
  std::string tools;  ///< "TX,TY,TZ;TX,TY,TZ"
  std::string criterion = "d";
  std::string angleUnit = "urad";
};

CLI::App* addPlanVerb(CLI::App& app, PlanArguments& arguments);

/// Fills arguments.options' grid, toolsMm, criterion and angle display from the text options;
/// throws UsageError or config::ConfigError.
void resolvePlanArguments(PlanArguments& arguments);

/// Plans and prints the expected uncertainties; returns 0 (a rank-deficient design is reported,
/// not an error). Throws config::ConfigError for bad files and options (exit status 2).
int runPlan(const PlanVerbOptions& options, std::ostream& out);

}  // namespace volcomp::cli
