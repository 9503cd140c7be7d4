// MachineModel: validation of the spec at construction, and the public evaluation functions,
// which run the fast paths (model/src/fast/) chosen for this CPU when the model was built. What
// they compute is defined by the reference composition (composition.cpp).

#include "volcomp/model/machine_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "fast/eval_plan.hpp"
#include "small_angle.hpp"

namespace volcomp::model {

namespace {

void requireFinite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw ModelError(std::string(what) + " holds a non-finite number");
}

}  // namespace

MachineModel::MachineModel(MachineModelSpec spec)
    : spec_(std::move(spec)), topology_(Topology::parse(spec_.topology)) {
  for (int i = 0; i < 18; ++i) {
    try {
      motion_[i] = ErrorFunction(spec_.motion[i]);
    } catch (const ModelError& e) {
      throw ModelError(motionName(i) + ": " + e.what());
    }
  }
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(spec_.locationRad[i])) {
      throw ModelError(locationName(i) + " is not a finite number");
    }
  }
  for (int k = 0; k < 3; ++k) {
    if (const auto& travel = spec_.travelMm[k]) {
      const double lo = (*travel)[0], hi = (*travel)[1];
      if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo <= hi)) {
        throw ModelError(std::string("travel of ") + "XYZ"[k] +
                         ": expected finite [min, max] with min <= max");
      }
    }
  }
  requireFinite(spec_.toolMm, "tool");
  requireFinite(spec_.workpieceMm, "workpiece");
  grids_.reserve(spec_.grids.size());
  for (std::size_t g = 0; g < spec_.grids.size(); ++g) {
    try {
      grids_.emplace_back(spec_.grids[g]);
    } catch (const ModelError& e) {
      throw ModelError("grids[" + std::to_string(g) + "]: " + e.what());
    }
  }
  // d_K - e_K is the K-th column of Rz Ry Rx - I, kept separately for full precision.
  std::array<Eigen::Vector3d, 3> directionMinusUnit;
  for (int k = 0; k < 3; ++k) {
    directionMinusUnit[k] =
        detail::rotationZYXMinusIdentity(spec_.locationRad[3 * k], spec_.locationRad[3 * k + 1],
                                         spec_.locationRad[3 * k + 2])
            .col(k);
    direction_[k] = directionMinusUnit[k];
    direction_[k][k] += 1.0;
  }
  plan_ = detail::buildPlan(spec_, topology_, direction_, directionMinusUnit);
}

const Eigen::Vector3d& MachineModel::axisDirection(Axis axis) const noexcept {
  return direction_[static_cast<int>(axis)];
}

std::uint8_t evaluateMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                            const Directions& directions, MotionValues& values) noexcept {
  return detail::PlanAccess::plan(model).kernels->motion(model, qMm, directions, values);
}

PointError composeError(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm,
                        EvalMode mode) noexcept {
  return detail::PlanAccess::plan(model).kernels->compose(model, ws, qMm, values, toolMm, mode);
}

void evaluateBatch(const MachineModel& model, Workspace& ws, std::span<const Eigen::Vector3d> qMm,
                   std::span<PointError> out, EvalMode mode,
                   std::span<const Directions> directions) noexcept {
  detail::PlanAccess::plan(model).kernels->many(model, ws, qMm.data(), directions.data(),
                                                directions.size(), out.data(),
                                                std::min(qMm.size(), out.size()), mode);
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Directions& directions, EvalMode mode) noexcept {
  return detail::PlanAccess::plan(model).kernels->evaluate(model, ws, qMm, model.toolMm(),
                                                           directions, mode);
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Eigen::Vector3d& toolMm, const Directions& directions,
                    EvalMode mode) noexcept {
  return detail::PlanAccess::plan(model).kernels->evaluate(model, ws, qMm, toolMm, directions,
                                                           mode);
}

void solveOffsetBatch(const MachineModel& model, Workspace& ws,
                      std::span<const Eigen::Vector3d> qMm, std::span<OffsetSolution> out,
                      std::span<const Directions> directions,
                      const OffsetOptions& options) noexcept {
  detail::PlanAccess::plan(model).kernels->solveMany(model, ws, qMm.data(), directions.data(),
                                                     directions.size(), out.data(),
                                                     std::min(qMm.size(), out.size()), options);
}

OffsetSolution solveOffset(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                           const Directions& directions, const OffsetOptions& options) noexcept {
  return detail::PlanAccess::plan(model).kernels->solve(model, ws, qMm, directions, options);
}

}  // namespace volcomp::model
