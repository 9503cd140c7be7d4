#pragma once
/// Measurement planning: which N of the candidate points (position and tool offset) to measure so
/// that the parameters of a calibration template are identified as well as possible, and what
/// uncertainty the parameters and the predicted errors will then have, before anyone measures.
///
/// Criterion: D-optimal on the identifiable subspace. J (3 rows per candidate, the sensitivity
/// matrix of the fit at the start values, columns scaled as in the fit) has rank r over all
/// candidates; with J_s = U S V^T the candidates' rows in the coordinates F = J_s V_r S_r^-1
/// (F^T F = I over all candidates) carry everything the candidates can identify. The planner
/// maximises log det(sum over the chosen points of F_i^T F_i): a greedy start, then exchanges (a
/// chosen point for a candidate) while the determinant grows.
///
/// Why D rather than minimax prediction variance: the determinant does not depend on the units or
/// the parametrisation of the template (scaling a parameter or replacing a table by a polynomial
/// of the same span multiplies it by a constant), it has cheap exact rank-one updates, and by
/// the Kiefer-Wolfowitz equivalence theorem the D-optimal design is also the design that
/// minimises the largest prediction variance over the candidate set (G-optimal), exactly for
/// designs with weights and closely for N-point designs: the planner reports that largest
/// prediction variance, which is what a user cares about.
///
/// The statistics of the chosen design come from the same analysis as a fit of measurements at
/// those points (analyse() on the same sensitivity matrix), so a design the planner calls rank
/// deficient is rank deficient in the fit, with the same combinations named.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/calibration/least_squares.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::calibration {

struct PlanCandidate {
  Eigen::Vector3d qMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d toolMm = Eigen::Vector3d::Zero();
  model::Directions directions{};
  int line = 0;  ///< line in the candidates file (0 for grid candidates)
};

struct PlanOptions {
  int points = 0;
  /// Standard deviation of the instrument per coordinate (mm): sigma of the parameters and of
  /// the predictions scale with it.
  double noiseMm = 1e-3;
  double rankTolerance = 1e-7;
  double identifiabilityThreshold = kIdentifiabilityThreshold;
  /// Exchange passes over the chosen points (each pass tries every chosen point once).
  int maxPasses = 20;
  std::function<void(const std::string&)> progress;
};

struct PlanResult {
  /// Indices into the candidates, in the order chosen.
  std::vector<std::size_t> selected;
  /// Rank of the sensitivity matrix over all candidates (what any design from them can reach).
  int candidateRank = 0;
  /// Analysis of the chosen design with s0 = noiseMm (no measurements yet): rank, parameter
  /// sigma, unidentifiable combinations.
  FitStatistics statistics;
  /// log det of the design's information on the identifiable subspace (coordinates F).
  double logDeterminant = 0.0;
  int exchanges = 0;
  /// Standard deviation (|sigma| of the 3-D predicted error, mm) at each candidate with the
  /// chosen design; NaN where the design does not determine the prediction.
  std::vector<double> candidateStdMm;
  double maxStdMm = 0.0;
  double rmsStdMm = 0.0;
  int undetermined = 0;
};

/// Candidates: every position of a grid over the template's travel with every tool.
std::vector<PlanCandidate> gridCandidates(const model::MachineModelSpec& spec,
                                          const std::array<int, 3>& nodes,
                                          const std::vector<Eigen::Vector3d>& toolsMm);

/// The measurement set of a design (errors 0): what a fit of measurements at the candidates sees.
MeasurementSet designMeasurements(const std::vector<PlanCandidate>& candidates,
                                  const std::vector<std::size_t>& chosen);

/// Plans options.points measurements among the candidates. Throws std::invalid_argument for
/// points < 1 or > the number of candidates.
PlanResult planMeasurements(const config::ModelDocument& templateDocument,
                            const std::vector<PlanCandidate>& candidates,
                            const PlanOptions& options);

/// The prediction uncertainty over the candidates for a given design (the same quantities as
/// PlanResult's), e.g. to compare a random design with a planned one.
PlanResult evaluateDesign(const config::ModelDocument& templateDocument,
                          const std::vector<PlanCandidate>& candidates,
                          const std::vector<std::size_t>& chosen, const PlanOptions& options);

}  // namespace volcomp::calibration
