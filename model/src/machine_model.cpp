#include "volcomp/model/machine_model.hpp"

// The four-lane vectors of evaluateBatch are passed between functions that are inlined or local
// to this file, so no calling convention crosses a boundary: GCC's note that AVX vectors are
// passed differently with and without AVX (-Wpsabi) does not apply to anything here.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "eval_plan.hpp"
#include "piecewise.hpp"
#include "simd.hpp"
#include "small_angle.hpp"
#include "volcomp/model/so3.hpp"

// GCC on x86-64: the kernels are built twice and picked at run time (see below). Clang spells the
// target pragma differently (and warns about GCC's), so it builds the baseline kernels only.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define VOLCOMP_MODEL_X86_DISPATCH 1
#else
#define VOLCOMP_MODEL_X86_DISPATCH 0
#endif

namespace volcomp::model {

namespace kernels_generic {
#include "eval_kernels.inc"
}  // namespace kernels_generic

#if VOLCOMP_MODEL_X86_DISPATCH
// The same code for CPUs with AVX2 and FMA: fused multiply-adds and VEX encodings take about 15 %
// off an evaluation (bench/model). Results differ from the generic build by rounding only.
#pragma GCC push_options
#pragma GCC target("avx2,fma")
namespace kernels_avx2 {
#include "eval_kernels.inc"
}  // namespace kernels_avx2
#pragma GCC pop_options
#endif

const detail::Kernels& detail::genericKernels() noexcept {
  return kernels_generic::kKernels;
}

namespace {

using detail::EvalPlan;

// The kernels for this CPU, chosen once per model.
const detail::Kernels& selectKernels() noexcept {
#if VOLCOMP_MODEL_X86_DISPATCH
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    return kernels_avx2::kKernels;
  }
#endif
  return kernels_generic::kKernels;
}

void requireFinite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw ModelError(std::string(what) + " holds a non-finite number");
}

std::shared_ptr<const EvalPlan> buildPlan(
    const MachineModelSpec& spec, const Topology& topology,
    const std::array<Eigen::Vector3d, 3>& direction,
    const std::array<Eigen::Vector3d, 3>& directionMinusUnit) {
  auto plan = std::make_shared<EvalPlan>();
  // Offsets into plan->data while it grows; turned into pointers once it is complete.
  struct GroupOffsets {
    int positions = 0;
    std::array<int, 3> coefficients{};
  };
  std::vector<GroupOffsets> groupOffsets;
  std::vector<int> polynomialOffsets;

  for (int k = 0; k < 3; ++k) {
    EvalPlan::AxisPlan& axis = plan->axes[k];
    axis.sign = topology.isWorkpieceSide(static_cast<Axis>(k)) ? -1.0 : 1.0;
    for (int i = 0; i < 3; ++i) {
      axis.direction[i] = direction[k][i];
      axis.directionMinusUnit[i] = directionMinusUnit[k][i];
    }
    axis.lowerMm = -std::numeric_limits<double>::infinity();
    axis.upperMm = std::numeric_limits<double>::infinity();
    if (spec.travelMm[k]) {
      axis.lowerMm = (*spec.travelMm[k])[0];
      axis.upperMm = (*spec.travelMm[k])[1];
    }

    axis.groupBegin = static_cast<int>(plan->groups.size());
    axis.polynomialBegin = static_cast<int>(plan->polynomials.size());
    std::array<bool, 6> done{};
    for (int slot = 0; slot < 6; ++slot) {
      const ErrorFunctionSpec& fs = spec.motion[k * 6 + slot];
      if (const double* constant = std::get_if<double>(&fs)) {
        axis.constants[slot] = *constant;
        done[slot] = true;
      } else if (const PolynomialSpec* poly = std::get_if<PolynomialSpec>(&fs)) {
        EvalPlan::Polynomial p;
        p.slot = slot;
        p.count = static_cast<int>(poly->coefficients.size());
        polynomialOffsets.push_back(static_cast<int>(plan->data.size()));
        plan->data.insert(plan->data.end(), poly->coefficients.begin(), poly->coefficients.end());
        plan->polynomials.push_back(p);
        done[slot] = true;
      }
    }
    // Tables over identical positions form one group.
    for (int slot = 0; slot < 6; ++slot) {
      if (done[slot]) continue;
      const std::vector<double>& positions =
          std::get<TableSpec>(spec.motion[k * 6 + slot]).positionsMm;
      EvalPlan::Group group;
      std::vector<std::array<std::vector<double>, 3>> curves;
      bool bidirectional = false;
      for (int other = slot; other < 6; ++other) {
        if (done[other]) continue;
        const TableSpec& table = std::get<TableSpec>(spec.motion[k * 6 + other]);
        if (table.positionsMm != positions) continue;
        done[other] = true;
        group.slots[group.entryCount++] = other;
        curves.push_back(detail::buildCurves(table));
        bidirectional = bidirectional || !table.valuesNegative.empty();
      }
      group.full = group.entryCount == 6;  // slots were taken in increasing order
      group.axis.count = static_cast<int>(positions.size());
      group.axis.uniform = detail::isUniform(positions);
      group.axis.first = positions.front();
      group.axis.last = positions.back();
      group.axis.invStep =
          static_cast<double>(positions.size() - 1) / (group.axis.last - group.axis.first);
      GroupOffsets offsets;
      offsets.positions = static_cast<int>(plan->data.size());
      plan->data.insert(plan->data.end(), positions.begin(), positions.end());
      const std::size_t n = static_cast<std::size_t>(group.entryCount);
      const std::size_t intervals = positions.size() - 1;
      for (int c = 0; c < 3; ++c) {
        if (c > 0 && !bidirectional) {
          offsets.coefficients[c] = offsets.coefficients[0];
          continue;
        }
        offsets.coefficients[c] = static_cast<int>(plan->data.size());
        std::vector<double> block(intervals * 4 * n);
        for (std::size_t e = 0; e < n; ++e) {
          for (std::size_t i = 0; i < intervals; ++i) {
            for (std::size_t p = 0; p < 4; ++p) {
              block[(4 * i + p) * n + e] = curves[e][c][4 * i + p];
            }
          }
        }
        plan->data.insert(plan->data.end(), block.begin(), block.end());
      }
      groupOffsets.push_back(offsets);
      plan->groups.push_back(group);
    }
    axis.groupEnd = static_cast<int>(plan->groups.size());
    axis.allTabulated = axis.groupEnd - axis.groupBegin == 1 && plan->groups.back().full;
    axis.polynomialEnd = static_cast<int>(plan->polynomials.size());
    axis.uniformTabulated = axis.allTabulated && plan->groups.back().axis.uniform &&
                            axis.polynomialBegin == axis.polynomialEnd;
  }
  const double* data = plan->data.data();
  for (std::size_t g = 0; g < plan->groups.size(); ++g) {
    plan->groups[g].axis.positions = data + groupOffsets[g].positions;
    for (int c = 0; c < 3; ++c) {
      plan->groups[g].coefficients[c] = data + groupOffsets[g].coefficients[c];
    }
  }
  for (std::size_t p = 0; p < plan->polynomials.size(); ++p) {
    plan->polynomials[p].coefficients = data + polynomialOffsets[p];
  }
  plan->allUniform = true;
  for (int k = 0; k < 3; ++k) {
    const EvalPlan::AxisPlan& axis = plan->axes[k];
    plan->allUniform = plan->allUniform && axis.uniformTabulated;
    if (!axis.uniformTabulated) continue;
    const EvalPlan::Group& group = plan->groups[axis.groupBegin];
    EvalPlan::UniformAxis& u = plan->uniform[k];
    u.lowerMm = axis.lowerMm;
    u.upperMm = axis.upperMm;
    u.first = group.axis.first;
    u.invStep = group.axis.invStep;
    u.top = static_cast<double>(group.axis.count - 1);
    u.lastInterval = group.axis.count - 2;
    u.coefficients = group.coefficients;
  }
  for (const Axis a : topology.toolSideFromFrame()) {
    plan->toolChain[plan->toolCount++] = static_cast<int>(a);
  }
  for (const Axis a : topology.workpieceSideFromFrame()) {
    plan->workpieceChain[plan->workpieceCount++] = static_cast<int>(a);
  }
  std::array<int, 3> chain{};
  for (int i = 0; i < 3; ++i) {
    chain[i] = i < plan->toolCount ? plan->toolChain[i] : plan->workpieceChain[i - plan->toolCount];
  }
  plan->chainPermutation = 2 * chain[0] + (chain[1] < chain[0] ? chain[1] : chain[1] - 1);
  plan->kernels = &selectKernels();
  return plan;
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
