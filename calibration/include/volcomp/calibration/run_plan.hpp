#pragma once
/// `volcomp plan TEMPLATE.json (--candidates CANDIDATES.csv | --grid NX,NY,NZ) --points N
/// [--tools "TX,TY,TZ;..."] [--noise MM] [--criterion d|i] [--out PLAN.csv] [--report PLAN.json]`:
/// the verb behind the CLI's argument parsing (see planning.hpp for the criterion).

#include <array>
#include <iosfwd>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace volcomp::calibration {

struct PlanVerbOptions {
  std::string templatePath;
  /// CSV x,y,z [,tx,ty,tz] [,direction]; without tool columns every candidate is taken with
  /// every tool of `toolsMm`.
  std::string candidatesPath;
  /// Grid nodes per axis over the template's travel (used when candidatesPath is empty).
  std::array<int, 3> grid{0, 0, 0};
  int points = 0;
  /// Tool offsets (mm); empty: the template's tool.
  std::vector<Eigen::Vector3d> toolsMm;
  double noiseMm = 1e-3;
  double rankTolerance = 1e-7;
  std::string outPath;     ///< the chosen points as CSV x,y,z,tx,ty,tz [,direction]
  std::string reportPath;  ///< JSON report
  std::string angleUnit = "urad";
  /// "d" (D-optimal, the default) or "i" (then an I-optimal exchange on the mean prediction
  /// variance over the candidates, started from the D-optimal design).
  std::string criterion = "d";
  /// Where the progress lines of the exchanges go (the CLI: stderr); null: into `out`.
  std::ostream* progress = nullptr;
};

/// Plans and prints the expected uncertainties; returns 0 (a rank-deficient design is reported,
/// not an error). Throws config::ConfigError for bad files and options (exit status 2).
int runPlan(const PlanVerbOptions& options, std::ostream& out);

}  // namespace volcomp::calibration
