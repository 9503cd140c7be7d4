#pragma once
/// What the report draws of a 3-axis model, as numbers: each error component sampled along its
/// axis, volumetric error maps over planes of the working volume, and statistics over the volume.
/// Evaluation goes through volcomp::model (evaluateBatch for maps and volume), exact mode, every
/// bidirectional table at the mean of its two curves unless a curve is asked for.
///
/// Units of the results: positions mm; error lengths µm; angles µrad. Errors are E(q) = p(q) -
/// p0(q) in the workpiece frame, as the model defines them.

#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::report {

inline constexpr double kUmPerMm = 1e3;
inline constexpr double kUradPerRad = 1e6;

/// The box the report samples: [min, max] mm per axis X, Y, Z.
struct WorkingVolume {
  std::array<std::array<double, 2>, 3> rangeMm{};
  /// Per axis: true when the range is the model's travel; false when the model gives none and
  /// the range spans the axis's tables and grids instead (or 0..100 mm when it has neither).
  std::array<bool, 3> fromTravel{};
};

WorkingVolume workingVolume(const model::MachineModel& model);

/// "X", "Y" or "Z".
std::string axisName(model::Axis axis);

/// One curve of one component: values (µm or µrad) at positions (mm).
struct ComponentCurve {
  /// Positive: the table's `values`; Negative: `values_negative`; Unknown: the only curve.
  model::Direction direction = model::Direction::Unknown;
  std::vector<double> positionsMm;
  std::vector<double> values;
};

/// A motion-error component as the report shows it.
struct ComponentView {
  int index = 0;  ///< motion index (model::motionIndex)
  model::Axis axis = model::Axis::X;
  bool angular = false;  ///< EA, EB, EC (µrad); else EX, EY, EZ (µm)
  std::string name;      ///< ISO 230-1 name, "EXX"
  std::string meaning;   ///< "positioning of X", "straightness of X in Y", "pitch of X"...
  std::string kind;      ///< "table (linear, 11 nodes, bidirectional)", "polynomial (degree 2)"
  std::string unit;      ///< "µm" or "µrad"
  std::vector<ComponentCurve> curves;  ///< one, or + and − for a bidirectional table
  /// Table nodes inside the range (mm, value), per curve as in `curves`.
  std::vector<std::vector<std::array<double, 2>>> nodes;
  double peakAbs = 0.0;  ///< largest |value| over the curves, display units
};

/// The non-zero motion components of the model in index order, each sampled at `samples` evenly
/// spaced positions over the working volume's range of its axis.
std::vector<ComponentView> componentViews(const model::MachineModel& model,
                                          const WorkingVolume& volume, int samples = 161);

/// The non-zero location errors (squareness), name and value in µrad.
std::vector<std::pair<std::string, double>> locationErrors(const model::MachineModel& model);

/// A plane of the working volume: `across` horizontal, `up` vertical, the third axis at `levelMm`.
struct PlaneSpec {
  model::Axis across = model::Axis::X;
  model::Axis up = model::Axis::Y;
  double levelMm = 0.0;
  int cellsAcross = 24;
  int cellsUp = 14;
  /// Arrows are drawn at every `arrowEvery`-th cell in both directions.
  int arrowEvery = 2;
};

/// The axis normal to a plane.
model::Axis normalAxis(const PlaneSpec& plane);

struct MapCell {
  double a0 = 0, a1 = 0, b0 = 0, b1 = 0;              ///< cell edges along `across` and `up`, mm
  double a = 0, b = 0;                                ///< the evaluated point (cell centre), mm
  Eigen::Vector3d errorUm = Eigen::Vector3d::Zero();  ///< E at the centre, X Y Z, µm
  double inPlaneA = 0, inPlaneB = 0;                  ///< E along `across` and `up`, µm
  double outOfPlane = 0;                              ///< E along the normal, µm
  double magnitude = 0;                               ///< |E|, µm
  bool arrow = false;                                 ///< an arrow is drawn at this cell
};

struct ErrorMap {
  PlaneSpec plane;
  std::vector<MapCell> cells;  ///< row by row: `up` outer, `across` inner
  double maxMagnitudeUm = 0, maxInPlaneUm = 0, maxAbsOutOfPlaneUm = 0;
};

/// Evaluates E at the centres of the plane's cells (evaluateBatch, exact mode).
ErrorMap errorMap(const model::MachineModel& model, model::Workspace& ws,
                  const WorkingVolume& volume, const PlaneSpec& plane);

/// The planes a report draws: XY at each of `zLevelsMm` (default: top, middle and bottom of the
/// Z range), XZ at the middle of Y, YZ at the middle of X; about `resolution` cells along the
/// longer side of each plane.
std::vector<PlaneSpec> reportPlanes(const WorkingVolume& volume, std::span<const double> zLevelsMm,
                                    int resolution = 24);

struct VolumeStatistics {
  int points = 0;
  double maxUm = 0, rmsUm = 0;
  Eigen::Vector3d maxAtMm = Eigen::Vector3d::Zero();
  std::array<double, 3> maxAbsPerAxisUm{};  ///< max |E_X|, |E_Y|, |E_Z|
  double maxAngularUrad = 0;                ///< max |angular error|
};

/// |E| over a perAxis^3 grid spanning the working volume (corners included).
VolumeStatistics volumeStatistics(const model::MachineModel& model, model::Workspace& ws,
                                  const WorkingVolume& volume, int perAxis = 11);

}  // namespace volcomp::report
