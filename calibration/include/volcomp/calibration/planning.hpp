#pragma once
/// Measurement planning: which N of the candidate points (position and tool offset) to measure so
/// that the parameters of a calibration template are identified as well as possible, and what
/// uncertainty the parameters and the predicted errors will then have, before anyone measures.
///
/// Criteria. J (3 rows per candidate, the sensitivity matrix of the fit at the start values,
/// columns scaled as in the fit; a template's smoothness rows below them) has rank r; with
/// J_s = U S V^T the rows in the coordinates F = J_s V_r S_r^-1 (F^T F = I) carry everything the
/// candidates can identify, and the smoothness rows' share is a prior information M_0 every
/// design has. With M = M_0 + sum over the chosen points of F_i^T F_i:
/// - D (default): maximise log det M: a greedy start, then exchanges (a chosen point for a
///   candidate) while the determinant grows. Invariant to the units and the parametrisation of
///   the template, cheap exact rank-3 updates.
/// - I: then, from the D-optimal design, exchanges that minimise the mean prediction variance
///   over the candidates, (1/C) sum_i trace(F_i M^-1 F_i^T) = trace(M^-1 W)/C with
///   W = sum_i F_i^T F_i, again by exact rank-3 (Woodbury) updates of M^-1 and F M^-1. Skipped
///   (the D design kept) when the design leaves a prediction undetermined.
/// The Kiefer-Wolfowitz theorem makes the D-optimal *weighted* design also minimise the largest
/// prediction variance (r/N sigma^2); designs of few points are far from it (the example of
/// docs/calibration.md: 5.1 sigma^2 for 60 points against r/N = 2.0), which is why the planner
/// reports the largest and the RMS prediction sigma of the design it chose.
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

/// What the exchange optimises (see the header comment): D the volume of the parameters'
/// confidence ellipsoid, I the mean prediction variance over the candidates.
enum class PlanCriterion { D, I };

struct PlanOptions {
  int points = 0;
  PlanCriterion criterion = PlanCriterion::D;
  /// Standard deviation of the instrument per coordinate (mm): sigma of the parameters and of
  /// the predictions scale with it.
  double noiseMm = 1e-3;
  double rankTolerance = 1e-7;
  double identifiabilityThreshold = kIdentifiabilityThreshold;
  /// Exchange passes over the chosen points (each pass tries every chosen point once).
  int maxPasses = 20;
  std::function<void(const std::string&)> progress;

  /// The settings, to name the one that cannot be used.
  enum class Field { Points, Noise, RankTolerance, MaxPasses };
  /// True when the options can be used (the number of candidates aside). Otherwise false, with
  /// *error saying what the value of *field must be; either pointer may be null.
  bool isValid(std::string* error, Field* field = nullptr) const;
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
  /// Exchanges of the D-optimal stage.
  int exchanges = 0;
  PlanCriterion criterion = PlanCriterion::D;
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
