// The evaluation plan of a MachineModel (eval_plan.hpp): the spec flattened for the fast paths.

#include "fast/eval_plan.hpp"

#include <limits>
#include <memory>
#include <variant>
#include <vector>

namespace volcomp::model::detail {

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
        curves.push_back(buildCurves(table));
        bidirectional = bidirectional || !table.valuesNegative.empty();
      }
      group.full = group.entryCount == 6;  // slots were taken in increasing order
      group.axis.count = static_cast<int>(positions.size());
      group.axis.uniform = isUniform(positions);
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

}  // namespace volcomp::model::detail
