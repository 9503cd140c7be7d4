#include "volcomp/model/machine_model.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "eval_plan.hpp"
#include "piecewise.hpp"
#include "small_angle.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::model {

namespace {

using detail::EvalPlan;

void requireFinite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw ModelError(std::string(what) + " holds a non-finite number");
}

std::shared_ptr<const EvalPlan> buildPlan(
    const MachineModelSpec& spec, const Topology& topology,
    const std::array<Eigen::Vector3d, 3>& direction,
    const std::array<Eigen::Vector3d, 3>& directionMinusUnit) {
  auto plan = std::make_shared<EvalPlan>();
  for (int k = 0; k < 3; ++k) {
    EvalPlan::AxisPlan& axis = plan->axes[k];
    const Axis axisK = static_cast<Axis>(k);
    axis.sign = topology.isWorkpieceSide(axisK) ? -1.0 : 1.0;
    axis.direction = direction[k];
    axis.directionMinusUnit = directionMinusUnit[k];
    axis.lowerMm = -std::numeric_limits<double>::infinity();
    axis.upperMm = std::numeric_limits<double>::infinity();
    if (spec.travelMm[k]) {
      axis.lowerMm = (*spec.travelMm[k])[0];
      axis.upperMm = (*spec.travelMm[k])[1];
    }

    axis.groupBegin = static_cast<int>(plan->groups.size());
    axis.polynomialBegin = static_cast<int>(plan->polynomials.size());
    // Tables of this axis, grouped by identical node positions (entries of a group contiguous).
    std::array<bool, 6> done{};
    for (int slot = 0; slot < 6; ++slot) {
      const ErrorFunctionSpec& fs = spec.motion[k * 6 + slot];
      if (const double* constant = std::get_if<double>(&fs)) {
        axis.constants[slot] = *constant;
        done[slot] = true;
      } else if (const PolynomialSpec* poly = std::get_if<PolynomialSpec>(&fs)) {
        EvalPlan::Polynomial p;
        p.slot = slot;
        p.begin = static_cast<int>(plan->data.size());
        plan->data.insert(plan->data.end(), poly->coefficients.begin(), poly->coefficients.end());
        p.end = static_cast<int>(plan->data.size());
        plan->polynomials.push_back(p);
        done[slot] = true;
      }
    }
    for (int slot = 0; slot < 6; ++slot) {
      if (done[slot]) continue;
      const std::vector<double>& positions =
          std::get<TableSpec>(spec.motion[k * 6 + slot]).positionsMm;
      EvalPlan::Group group;
      group.count = static_cast<int>(positions.size());
      group.uniform = detail::isUniform(positions);
      group.first = positions.front();
      group.last = positions.back();
      group.invStep = static_cast<double>(positions.size() - 1) / (group.last - group.first);
      group.positions = static_cast<int>(plan->data.size());
      plan->data.insert(plan->data.end(), positions.begin(), positions.end());
      group.entryBegin = static_cast<int>(plan->entries.size());
      for (int other = slot; other < 6; ++other) {
        if (done[other]) continue;
        const TableSpec& table = std::get<TableSpec>(spec.motion[k * 6 + other]);
        if (table.positionsMm != positions) continue;
        done[other] = true;
        const std::array<std::vector<double>, 3> curves = detail::buildCurves(table);
        EvalPlan::Entry entry;
        entry.slot = other;
        for (int c = 0; c < 3; ++c) {
          if (c > 0 && curves[c] == curves[0]) {
            entry.curve[c] = entry.curve[0];
            continue;
          }
          entry.curve[c] = static_cast<int>(plan->data.size());
          plan->data.insert(plan->data.end(), curves[c].begin(), curves[c].end());
        }
        plan->entries.push_back(entry);
      }
      group.entryEnd = static_cast<int>(plan->entries.size());
      plan->groups.push_back(group);
    }
    axis.groupEnd = static_cast<int>(plan->groups.size());
    axis.polynomialEnd = static_cast<int>(plan->polynomials.size());
  }
  for (const Axis a : topology.toolSideFromFrame()) {
    plan->toolChain[plan->toolCount++] = static_cast<int>(a);
  }
  for (const Axis a : topology.workpieceSideFromFrame()) {
    plan->workpieceChain[plan->workpieceCount++] = static_cast<int>(a);
  }
  return plan;
}

// Per-carriage data of one evaluation: R_K - I and the error translation e_K.
struct Carriages {
  std::array<Eigen::Matrix3d, 3> rotationMinusIdentity;
};

void computeCarriages(const MotionValues& v, Carriages& c) noexcept {
  for (int k = 0; k < 3; ++k) {
    const double* e = v.data() + 6 * k;
    c.rotationMinusIdentity[k] = detail::rotationZYXMinusIdentity(e[3], e[4], e[5]);
  }
}

// E(q) without grids, composed in deviation form: every partial product is carried as its
// nominal value plus a deviation, and only deviations are accumulated, so that E keeps full
// relative precision instead of being the difference of two positions of ~1e3 mm.
// Tool side, carriage K applied to p = p0 + dp (p0 the nominal partial point):
//   R p + e + q d = (p0 + q e_K) + [dp + (R - I) p + e + q (d - e_K)].
// Workpiece side, C_K^-1 x = R^T (x - e + q d) with x = x0 + dx:
//   x - e + q d = (x0 + q e_K) + D,  D = dx - e + q (d - e_K),
//   R^T (x0 + q e_K + D) = (x0 + q e_K) + [D + (R^T - I)(x0 + q e_K + D)].
// The nominal result is q + t (and -w on both), so E is the final deviation.
Eigen::Vector3d positionDeviation(const EvalPlan& plan, const Carriages& c,
                                  const Eigen::Vector3d& q, const MotionValues& v,
                                  const Eigen::Vector3d& tool) noexcept {
  Eigen::Vector3d nominal = tool;
  Eigen::Vector3d deviation = Eigen::Vector3d::Zero();
  for (int i = plan.toolCount; i-- > 0;) {
    const int k = plan.toolChain[i];
    const double* e = v.data() + 6 * k;
    deviation += c.rotationMinusIdentity[k] * (nominal + deviation) +
                 Eigen::Vector3d(e[0], e[1], e[2]) + q[k] * plan.axes[k].directionMinusUnit;
    nominal[k] += q[k];
  }
  for (int i = 0; i < plan.workpieceCount; ++i) {
    const int k = plan.workpieceChain[i];
    const double* e = v.data() + 6 * k;
    nominal[k] += q[k];
    deviation += q[k] * plan.axes[k].directionMinusUnit - Eigen::Vector3d(e[0], e[1], e[2]);
    deviation += c.rotationMinusIdentity[k].transpose() * (nominal + deviation);
  }
  return deviation;
}

// rot(H_WT) = R_W1^T ... R_Wn^T R_T1 ... R_Tn.
Eigen::Matrix3d composedRotation(const EvalPlan& plan, const Workspace& ws) noexcept {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (plan.toolCount > 0) {
    r = ws.rotation[plan.toolChain[plan.toolCount - 1]];
    for (int i = plan.toolCount - 1; i-- > 0;) r = ws.rotation[plan.toolChain[i]] * r;
  }
  for (int i = 0; i < plan.workpieceCount; ++i) {
    r = ws.rotation[plan.workpieceChain[i]].transpose() * r;
  }
  return r;
}

void addGrids(const MachineModel& model, const Eigen::Vector3d& q, Eigen::Vector3d& p) noexcept {
  for (const Grid& grid : model.grids()) p[grid.component()] += grid.valueMm(q.data());
}

Eigen::Vector3d positionError(const MachineModel& model, const EvalPlan& plan, Carriages& c,
                              const Eigen::Vector3d& q, const MotionValues& values,
                              const Eigen::Vector3d& tool) noexcept {
  computeCarriages(values, c);
  Eigen::Vector3d error = positionDeviation(plan, c, q, values, tool);
  addGrids(model, q, error);
  return error;
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
  plan_ = buildPlan(spec_, topology_, direction_, directionMinusUnit);
}

const Eigen::Vector3d& MachineModel::axisDirection(Axis axis) const noexcept {
  return direction_[static_cast<int>(axis)];
}

std::uint8_t evaluateMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                            const Directions& directions, MotionValues& values) noexcept {
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  const double* data = plan.data.data();
  std::uint8_t clamped = 0;
  for (int k = 0; k < 3; ++k) {
    const EvalPlan::AxisPlan& axis = plan.axes[k];
    double q = qMm[k];
    if (q < axis.lowerMm) {
      q = axis.lowerMm;
      clamped = static_cast<std::uint8_t>(clamped | (1u << k));
    } else if (q > axis.upperMm) {
      q = axis.upperMm;
      clamped = static_cast<std::uint8_t>(clamped | (1u << k));
    }
    double* out = values.data() + 6 * k;
    for (int s = 0; s < 6; ++s) out[s] = axis.constants[s];
    const int curve = detail::curveIndex(directions[k]);
    for (int g = axis.groupBegin; g < axis.groupEnd; ++g) {
      const EvalPlan::Group& group = plan.groups[g];
      detail::TableAxis lookup;
      lookup.positions = data + group.positions;
      lookup.count = group.count;
      lookup.uniform = group.uniform;
      lookup.first = group.first;
      lookup.last = group.last;
      lookup.invStep = group.invStep;
      const detail::TableLocation at = lookup.locate(q);
      for (int e = group.entryBegin; e < group.entryEnd; ++e) {
        const EvalPlan::Entry& entry = plan.entries[e];
        out[entry.slot] = detail::evaluateCubic(data + entry.curve[curve], at);
      }
    }
    for (int p = axis.polynomialBegin; p < axis.polynomialEnd; ++p) {
      const EvalPlan::Polynomial& poly = plan.polynomials[p];
      double sum = 0.0;
      for (int i = poly.end; i-- > poly.begin;) sum = sum * q + data[i];
      out[poly.slot] = sum;
    }
  }
  return clamped;
}

PointError composeError(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm,
                        EvalMode mode) noexcept {
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  Carriages c;
  PointError result;
  result.errorMm = positionError(model, plan, c, qMm, values, toolMm);
  if (mode == EvalMode::Exact) {
    for (int k = 0; k < 3; ++k) {
      const double* e = values.data() + 6 * k;
      ws.rotation[k] = c.rotationMinusIdentity[k] + Eigen::Matrix3d::Identity();
      ws.translationMm[k] =
          Eigen::Vector3d(e[0], e[1], e[2]) + (plan.axes[k].sign * qMm[k]) * plan.axes[k].direction;
    }
    result.angularErrorRad = rotationVector(composedRotation(plan, ws));
  } else {
    // First order the small rotations simply add: tool side +w, workpiece side -w.
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const double* e = values.data() + 6 * k;
      sum += plan.axes[k].sign * Eigen::Vector3d(e[3], e[4], e[5]);
    }
    result.angularErrorRad = sum;
  }
  return result;
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Directions& directions, EvalMode mode) noexcept {
  return evaluate(model, ws, qMm, model.toolMm(), directions, mode);
}

PointError evaluate(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                    const Eigen::Vector3d& toolMm, const Directions& directions,
                    EvalMode mode) noexcept {
  const std::uint8_t clamped = evaluateMotion(model, qMm, directions, ws.motion);
  PointError result = composeError(model, ws, qMm, ws.motion, toolMm, mode);
  result.clampedAxes = clamped;
  return result;
}

OffsetSolution solveOffset(const MachineModel& model, Workspace& ws, const Eigen::Vector3d& qMm,
                           const Directions& directions, const OffsetOptions& options) noexcept {
  const EvalPlan& plan = detail::PlanAccess::plan(model);
  const Eigen::Vector3d& tool = model.toolMm();
  OffsetSolution solution;
  // Both modes compose the position the same way (see EvalMode), so options.mode changes nothing.
  Carriages c;
  std::uint8_t clamped = evaluateMotion(model, qMm, directions, ws.motion);
  Eigen::Vector3d offset = -positionError(model, plan, c, qMm, ws.motion, tool);
  double residualNorm = std::numeric_limits<double>::infinity();
  int iteration = 0;
  while (iteration < options.maxIterations) {
    ++iteration;
    const Eigen::Vector3d commanded = qMm + offset;
    clamped = evaluateMotion(model, commanded, directions, ws.motion);
    // p(q + o) - p0(q) = E(q + o) + o, formed without subtracting two large positions.
    const Eigen::Vector3d residual =
        positionError(model, plan, c, commanded, ws.motion, tool) + offset;
    residualNorm = residual.norm();
    if (!std::isfinite(residualNorm)) break;
    if (residualNorm < options.toleranceMm) {
      solution.converged = true;
      break;
    }
    if (iteration == options.maxIterations) break;  // keep the offset the residual belongs to
    offset -= residual;
  }
  solution.offsetMm = offset;
  solution.iterations = iteration;
  solution.residualMm = residualNorm;
  solution.clampedAxes = clamped;
  return solution;
}

}  // namespace volcomp::model
