#include "volcomp/nc/offset_field.hpp"

#include <algorithm>
#include <limits>
#include <variant>

namespace volcomp::nc {
namespace {

void addSpacing(const std::vector<double>& nodes, double& smallest) {
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    smallest = std::min(smallest, nodes[i] - nodes[i - 1]);
  }
}

}  // namespace

OffsetField::OffsetField(std::shared_ptr<const model::MachineModel> model, model::EvalMode mode)
    : model_(std::move(model)),
      mode_(mode),
      smallestSpacing_(std::numeric_limits<double>::infinity()) {
  const model::MachineModelSpec& spec = model_->spec();
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double>& k = kinks_[static_cast<std::size_t>(axis)];
    for (int kind = 0; kind < 6; ++kind) {
      const int index = axis * 6 + kind;
      if (model_->motion(index).isZero()) continue;
      const auto* table =
          std::get_if<model::TableSpec>(&spec.motion[static_cast<std::size_t>(index)]);
      if (table == nullptr || table->positionsMm.empty()) continue;
      if (!table->valuesNegative.empty()) bidirectional_ |= static_cast<std::uint8_t>(1u << axis);
      const std::vector<double>& p = table->positionsMm;
      addSpacing(p, smallestSpacing_);
      switch (table->interpolation) {
        case model::Interpolation::Linear:
          k.insert(k.end(), p.begin(), p.end());
          break;
        case model::Interpolation::Quadratic:
          for (std::size_t i = 0; i < p.size(); i += 2) k.push_back(p[i]);
          break;
        case model::Interpolation::Cubic:
          k.push_back(p.front());
          k.push_back(p.back());
          break;
      }
    }
    for (const model::Grid& grid : model_->grids()) {
      const model::GridSpec& g = grid.spec();
      for (std::size_t j = 0; j < g.over.size(); ++j) {
        if (static_cast<int>(g.over[j]) != axis) continue;
        k.insert(k.end(), g.axesMm[j].begin(), g.axesMm[j].end());
        addSpacing(g.axesMm[j], smallestSpacing_);
      }
    }
    if (const auto& travel = spec.travelMm[static_cast<std::size_t>(axis)]) {
      k.push_back((*travel)[0]);
      k.push_back((*travel)[1]);
    }
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
  }
}

void OffsetField::solve(std::span<const Vec3> q, std::span<const model::Directions> dirs,
                        std::span<OffsetSample> out) {
  // The batch path solves four points per SIMD register; the solutions go through a buffer that
  // keeps the largest size seen, so a steady stream of chunks allocates nothing.
  if (solutions_.size() < q.size()) solutions_.resize(q.size());
  const std::span<model::OffsetSolution> solved(solutions_.data(), q.size());
  model::OffsetOptions options;
  options.mode = mode_;
  model::solveOffsetBatch(*model_, ws_, q, solved, dirs, options);
  for (std::size_t i = 0; i < q.size(); ++i) {
    out[i].offsetMm = solved[i].offsetMm;
    out[i].clampedAxes = solved[i].clampedAxes;
    out[i].converged = solved[i].converged;
  }
}

}  // namespace volcomp::nc
