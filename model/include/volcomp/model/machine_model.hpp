#pragma once
/// The 3-axis volumetric error model (model format sections 3, 4, 6): an immutable MachineModel,
/// a preallocated Workspace, and free evaluation functions `algo(model, workspace, q)` in the
/// style of Pinocchio's Model/Data. Evaluation is noexcept and never allocates.
///
/// Frames: F machine frame (bed), W workpiece, T tool tip. `frameMworkpiece` = H_FW,
/// `frameMtool` = H_FT, `workpieceMtool` = H_WT = H_FW^-1 H_FT (composition.hpp writes them out).
/// Position error E(q) = p(q) - p0(q) in mm in the workpiece frame, p(q) = translation of H_WT plus
/// grid terms, p0(q) = q + t - w. Angular error: rotation vector (log map) of rot(H_WT), rad.
/// Commanded positions q and offsets o are machine-axis positions in mm.
///
/// What these functions compute is defined by the reference composition (composition.hpp:
/// evaluateReference, one homogeneous transform per carriage). They compute it by faster paths
/// (a flattened table plan, the chain in deviation form so that E keeps its own relative
/// precision, short angle series, four points per SIMD register for the batch functions), held
/// to the reference by the tests: 1e-11 mm and 1e-14 rad.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "volcomp/model/error_function.hpp"
#include "volcomp/model/grid.hpp"
#include "volcomp/model/topology.hpp"
#include "volcomp/model/types.hpp"

namespace volcomp::model {

namespace detail {
struct EvalPlan;
struct PlanAccess;
}  // namespace detail

/// Everything a model file says, in internal units (mm, rad). Plain data.
struct MachineModelSpec {
  std::string name;
  std::string topology = "FXYZ";
  /// Travel [min, max] per axis (mm); std::nullopt = unbounded.
  std::array<std::optional<std::array<double, 2>>, 3> travelMm{};
  Eigen::Vector3d toolMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d workpieceMm = Eigen::Vector3d::Zero();
  /// The 18 motion errors, indexed by motionIndex(axis, kind); default constant 0.
  std::array<ErrorFunctionSpec, 18> motion{};
  /// The 9 location errors (rad), indexed by locationIndex(axis, rotationAbout).
  std::array<double, 9> locationRad{};
  std::vector<GridSpec> grids;
};

enum class EvalMode : std::uint8_t {
  /// The rigid-body composition: E(q) and the angular error as evaluateReference defines them.
  Exact,
  /// Small-displacement angular error: the sum of the tool-side error angles (EA, EB, EC) minus
  /// the workpiece-side ones, which differs from Exact's log map by O(|w|^2) (a few 1e-6 rad at
  /// 1e-3 rad angles). The position is composed exactly, as in Exact (a second-order expansion of
  /// the rotations leaves third-order terms of |w|^3 |v| / 6 per carriage, 7e-6 mm with every
  /// angle at 1e-3 rad on 2 m arms, beyond the format's 1e-6 mm for this mode), so E and
  /// solveOffset are the same in both modes.
  FirstOrder,
};

/// Values of the 18 motion-error components at one point (internal units), indexed by motionIndex.
using MotionValues = std::array<double, 18>;

/// Result of one evaluation.
struct PointError {
  Eigen::Vector3d errorMm = Eigen::Vector3d::Zero();          ///< E(q) = p(q) - p0(q), mm, W frame
  Eigen::Vector3d angularErrorRad = Eigen::Vector3d::Zero();  ///< rotation vector of rot(H_WT), rad
  /// Bit K set when axis K was outside its travel and its error functions were evaluated at the
  /// nearest end of the travel.
  std::uint8_t clampedAxes = 0;
};

/// Result of the compensation-offset solve p(q + o) = p0(q).
struct OffsetSolution {
  Eigen::Vector3d offsetMm = Eigen::Vector3d::Zero();
  int iterations = 0;
  bool converged = false;
  /// |p(q + o) - p0(q)| at the returned offset, mm.
  double residualMm = 0.0;
  std::uint8_t clampedAxes = 0;
};

struct OffsetOptions {
  int maxIterations = 50;
  double toleranceMm = 1e-9;
  EvalMode mode = EvalMode::Exact;
};

/// Immutable model. Construct once (may throw ModelError), evaluate many times.
class MachineModel {
 public:
  explicit MachineModel(MachineModelSpec spec);

  const MachineModelSpec& spec() const noexcept { return spec_; }
  const Topology& topology() const noexcept { return topology_; }
  const ErrorFunction& motion(int index) const noexcept { return motion_[index]; }
  const std::vector<Grid>& grids() const noexcept { return grids_; }
  /// Unit direction d_K = Rz(EC0K) Ry(EB0K) Rx(EA0K) e_K of axis K (precomputed).
  const Eigen::Vector3d& axisDirection(Axis axis) const noexcept;
  const Eigen::Vector3d& toolMm() const noexcept { return spec_.toolMm; }
  const Eigen::Vector3d& workpieceMm() const noexcept { return spec_.workpieceMm; }

 private:
  MachineModelSpec spec_;
  Topology topology_;
  std::array<ErrorFunction, 18> motion_;
  std::vector<Grid> grids_;
  std::array<Eigen::Vector3d, 3> direction_;
  // Flattened evaluation data (tables grouped per axis, travel limits, chain order) built once by
  // the constructor; shared between copies because it is immutable.
  std::shared_ptr<const detail::EvalPlan> plan_;
  friend struct detail::PlanAccess;
};

/// Per-thread evaluation state (one per thread; the model itself is shared). Every evaluation
/// leaves the 18 motion-error values (internal units, motionIndex order) of the last point it
/// evaluated in `motion`.
struct Workspace {
  MotionValues motion{};
};

/// Evaluate the 18 motion-error functions at q (clamped to travel), writing `values`.
/// Returns the clamped-axes bitmask.
std::uint8_t evaluateMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                            const Directions& directions, MotionValues& values) noexcept;

/// Compose the error for given motion values (no function evaluation; grids are added).
/// Used by evaluate() and by calibration, which supplies its own component values.
PointError composeError(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm,
                        EvalMode mode = EvalMode::Exact) noexcept;

/// E(q) and the angular error with the model's own tool offset.
PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Directions& directions = {}, EvalMode mode = EvalMode::Exact) noexcept;

/// Same with a tool offset (mm) that overrides the model's.
PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Eigen::Vector3d& toolMm, const Directions& directions = {},
                    EvalMode mode = EvalMode::Exact) noexcept;

/// E(q) and the angular error of many points with the model's own tool offset: out[i] is what
/// evaluate(model, ws, qMm[i], directions[i], mode) returns, to rounding (the tests hold it to
/// 1e-12 mm and rad). For throughput (error maps, NC programs, calibration residuals): four points
/// are evaluated side by side in the lanes of a SIMD register; a block of four in which a point's
/// error angles are large (the sum of their squares reaches (1e-2 rad)^2) or a value is not
/// finite is evaluated point by point.
/// `directions` is empty (every direction Unknown) or gives the direction of point i at i (points
/// beyond its end take Unknown). Evaluates min(qMm.size(), out.size()) points; leaves the motion
/// values of the last one in ws.motion, as evaluate() does.
void evaluateBatch(const MachineModel& model, Workspace& ws, std::span<const Eigen::Vector3d> qMm,
                   std::span<PointError> out, EvalMode mode = EvalMode::Exact,
                   std::span<const Directions> directions = {}) noexcept;

/// Compensation offset o with p(q + o) = p0(q), by the fixed point o <- o + p0(q) - p(q + o)
/// starting at o = -E(q). Non-convergence is reported in the result, never hidden.
OffsetSolution solveOffset(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                           const Directions& directions = {},
                           const OffsetOptions& options = {}) noexcept;

/// Compensation offsets of many points: out[i] is what solveOffset(model, ws, qMm[i],
/// directions[i], options) returns, to rounding (the offsets agree to 1e-12 mm).
///
/// For each commanded point q = qMm[i] (mm, machine axes) it solves p(q + o) = p0(q) for the
/// offset o (mm, added to the commanded axis positions): the tool then reaches the nominal point
/// p0(q) = q + t - w in the workpiece frame. Fixed point o <- o + p0(q) - p(q + o) =
/// o - (E(q + o) + o), starting at o = -E(q), until |p(q + o) - p0(q)| < options.toleranceMm or
/// options.maxIterations evaluations. Both EvalMode values give the same offset (the position is
/// composed exactly in both), so options.mode changes nothing.
///
/// Convergence is data, per point: out[i].converged, .iterations, .residualMm (|p(q + o) - p0(q)|
/// at the returned o, mm) and .clampedAxes (axes outside their travel at q + o). A point whose
/// residual is not finite (NaN or infinite input) stops with converged = false.
///
/// Built for throughput (NC programs, error maps): the points are solved four at a time in the
/// lanes of evaluateBatch, each lane stopping on its own. `directions` is empty (every direction
/// Unknown) or gives the direction of point i at i (points beyond its end take Unknown). Solves
/// min(qMm.size(), out.size()) points; noexcept and allocation-free. Leaves in ws.motion the
/// motion values of the last point at its last evaluated position.
void solveOffsetBatch(const MachineModel& model, Workspace& ws,
                      std::span<const Eigen::Vector3d> qMm, std::span<OffsetSolution> out,
                      std::span<const Directions> directions = {},
                      const OffsetOptions& options = {}) noexcept;

}  // namespace volcomp::model
