#pragma once
/// `volcomp-sim nc-run`: the simulated machine runs an NC program (no controller link, no live
/// compensation: the experiment of Dobariya, Patel and Jani, who compensate the program itself). The machine has its
/// TRUE error model; along every feed move of the program, sampled every `stepMm`, the tool tip
/// q + E(q) is compared with the path of a REFERENCE program (the original part program): the
/// error is the tip's distance from that path (contour error), with the direction of travel of
/// each axis as on the reference path there. Running the original program against itself gives
/// the error without compensation; running a `volcomp nc` output gives it with compensation.
/// Rapids are not part of the path; moves `volcomp nc` marked as reversal or lead-in moves are
/// skipped (the machine takes up a reversal there).

#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "volcomp/sim/nc_program.hpp"

namespace volcomp::sim {

struct NcRunOptions {
  NcProgramSpec program;
  NcProgramSpec reference;
  std::string trueModel;
  double stepMm = 0.05;
};

struct NcRunReport {
  long samples = 0;
  double pathMm = 0.0;  ///< length of the sampled feed moves
  double rmsUm = 0.0;   ///< contour error, RMS over the samples
  double maxUm = 0.0;
  std::array<double, 3> maxAtMm{};    ///< axis position of the sample with the largest error
  std::array<double, 3> rmsAxisUm{};  ///< components of the error vector
  std::array<double, 3> maxAxisUm{};
  long markedMoves = 0;
  nlohmann::json toJson() const;
};

/// Throws config::ConfigError / nc::NcError for bad files.
NcRunReport runNcProgram(const NcRunOptions& options);

/// The contour error of a run a machine recorded: `recordFile` is CSV with the header
/// x,y,z,ox,oy,oz and one row per sample (mm): the axis positions q the controller commanded and
/// the external offsets o it applied, so that the axes stand at q + o (as the LinuxCNC tests
/// record them). Each sample's tool tip (q + o) + E(q + o) is compared with the reference path,
/// with the directions of travel of the nearest reference piece. pathMm is the length of the
/// recorded polyline; markedMoves is 0. Throws config::ConfigError for a bad file (file:row).
NcRunReport measureRecordedRun(const std::string& recordFile, const NcProgramSpec& reference,
                               const std::string& trueModel);

/// The `nc-run` command line (argv[0] is "nc-run"): prints the report as one JSON line on stdout
/// and a summary on stderr; returns the exit status.
int ncRunMain(int argc, char** argv);

}  // namespace volcomp::sim
