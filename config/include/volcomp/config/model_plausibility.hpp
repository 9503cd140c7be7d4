#pragma once
/// Is a 3-axis model plausible for a machine tool, and does it fit the daemon's limiter? What
/// `volcomp check` and volcompd (at start, `--check-config` and every reload) ask before a model
/// may compensate a machine.
///
/// The model is evaluated over a grid of its travel (the axis' travel when the file gives one,
/// else the span of that axis' tables and grids, else the single position 0), for both directions
/// of travel: the volumetric error E(q) (mm, workpiece frame) and the compensation offset o(q)
/// with p(q + o) = p0(q) (mm, machine axes) at every grid point. Each error component is sampled
/// along its own axis over the same range (tables at every node and between them).
///
/// A model is refused (the first problem found, as a ConfigError naming the file and key path):
/// - without "error_units" (values would silently be read as mm and rad);
/// - with a translational component, a grid value or |E(q)| beyond the plausible length
///   (default 1 mm) or an angular component beyond the plausible angle (default 1e-2 rad);
///   the file may override both with "plausibility" (ModelDocument::plausibility);
/// - when E(q) or o(q) is NaN or infinite anywhere on the grid, or the offset solve does not
///   converge there;
/// - when the largest |o| on an axis exceeds the limiter's max_offset (when one is given): the
///   limiter would clamp the correction and the machine would be miscompensated.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::config {

/// Grid points per axis for the volumetric evaluation (the travel ends included).
inline constexpr int kPlausibilityGridPoints = 21;

/// What the evaluation over the grid found: numerical outcomes, no verdict.
struct ModelAssessment {
  /// Range sampled per axis (mm) and whether it is the file's travel.
  std::array<std::array<double, 2>, 3> rangeMm{};
  std::array<bool, 3> rangeIsTravel{};
  std::array<int, 3> gridPoints{};
  std::size_t points = 0;  ///< grid points evaluated (per direction)

  double peakErrorMm = 0.0;  ///< largest |E(q)| (3-D norm)
  Eigen::Vector3d peakErrorAtMm = Eigen::Vector3d::Zero();
  double peakAngleRad = 0.0;  ///< largest |angular error| (rotation vector norm)
  /// Largest |o_K| per axis and where it occurs.
  std::array<double, 3> peakOffsetMm{};
  std::array<Eigen::Vector3d, 3> peakOffsetAtMm{};

  /// Largest |value| of each motion component over its axis' range (mm or rad), of each
  /// location error, and of each grid.
  std::array<double, 18> motionPeak{};
  std::array<double, 18> motionPeakAtMm{};
  std::array<double, 9> locationPeakRad{};
  std::vector<double> gridPeakMm;

  /// First grid point where E or o was not finite, or the solve did not converge.
  std::optional<Eigen::Vector3d> nonFiniteAtMm;
  std::optional<Eigen::Vector3d> notConvergedAtMm;
};

/// Evaluates `model` (built from `doc`'s spec) over the grid described above.
ModelAssessment assessModel(const model::MachineModel& model);

/// The limiter a model must fit, and where that limit comes from (for the message).
/// (The daemon configuration's limiter gives it: offsetBoundOf in config/daemon_config.hpp.)
struct OffsetBound {
  std::array<double, 3> maxOffsetMm{};  ///< per axis X, Y, Z
  std::string source;                   ///< e.g. "limiter.max_offset_mm of volcompd.json"
};

/// Throws ConfigError (the model's file, the key path of the culprit, what was found and what
/// to do) on the first problem listed at the top of this header; returns when there is none.
/// `requireUnits` false skips the "error_units" rule (calibration templates).
void requirePlausible(const ModelDocument& doc, const ModelAssessment& assessment,
                      const std::optional<OffsetBound>& bound, bool requireUnits = true);

/// Loads nothing: builds the model of a 3-axis document, assesses it and applies
/// requirePlausible. Returns the assessment (for a summary). D-H chains are not assessed.
std::optional<ModelAssessment> checkPlausible(const ModelDocument& doc,
                                              const std::optional<OffsetBound>& bound);

}  // namespace volcomp::config
