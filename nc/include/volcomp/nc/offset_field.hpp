#pragma once
/// The model as the NC compensation sees it: the compensation offset o(q) (mm) at machine axis
/// positions q with the direction of travel of each axis (the daemon's fixed point
/// p(q + o) = p0(q), see the model library), and the places along each axis where o is not
/// smooth (kinks), which the splitting of moves treats as section boundaries.
///
/// Kinks of axis K (positions in mm along K): every node of a linear table of a component of K;
/// the element boundaries (every second node) of a quadratic table; the first and last node of a
/// cubic table (the value is held outside it); the nodes of grids along K; the travel limits of K.
/// Between kinks o is at least once continuously differentiable along any straight line or arc
/// (natural cubic splines and polynomials are smooth, the rigid-body composition too). The offset
/// is solved at q + o, so a kink of o in q lies |o_K| (micrometres) from the listed position:
/// dense checking covers that (see docs/nc.md).

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "volcomp/model/machine_model.hpp"
#include "volcomp/nc/move.hpp"

namespace volcomp::nc {

struct OffsetSample {
  Vec3 offsetMm = Vec3::Zero();
  std::uint8_t clampedAxes = 0;  ///< bit K: axis K outside the travel (evaluated at its end)
  bool converged = true;
};

class OffsetField {
 public:
  OffsetField(std::shared_ptr<const model::MachineModel> model, model::EvalMode mode);

  /// Offsets at n = q.size() points, point i with directions dirs[i] (dirs.size() == q.size()).
  /// The one place where the model's offset solve is called: model::solveOffsetBatch, four
  /// points at a time.
  void solve(std::span<const Vec3> q, std::span<const model::Directions> dirs,
             std::span<OffsetSample> out);

  /// Bit K set when some table of axis K is bidirectional (its direction of travel matters).
  std::uint8_t bidirectionalAxes() const noexcept { return bidirectional_; }
  /// Sorted kink positions of axis K (mm).
  const std::vector<double>& kinks(int axis) const noexcept {
    return kinks_[static_cast<std::size_t>(axis)];
  }
  /// Smallest spacing between consecutive nodes of any non-zero table or grid (mm); +inf when
  /// the model has none.
  double smallestNodeSpacingMm() const noexcept { return smallestSpacing_; }
  const model::MachineModel& model() const noexcept { return *model_; }

 private:
  std::shared_ptr<const model::MachineModel> model_;
  model::EvalMode mode_;
  model::Workspace ws_;
  std::vector<model::OffsetSolution> solutions_;
  std::array<std::vector<double>, 3> kinks_;
  std::uint8_t bidirectional_ = 0;
  double smallestSpacing_;
};

}  // namespace volcomp::nc
