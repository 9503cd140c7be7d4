#include "volcomp/loop/compensation_model.hpp"

#include <utility>

namespace volcomp::loop {

MachineModelCompensation::MachineModelCompensation(model::MachineModel model, std::string name)
    : model_(std::move(model)), name_(std::move(name)) {}

ModelOffset MachineModelCompensation::offset(const std::array<double, 3>& qMm,
                                             const model::Directions& directions) noexcept {
  const Eigen::Vector3d q(qMm[0], qMm[1], qMm[2]);
  const model::OffsetSolution solution = model::solveOffset(model_, workspace_, q, directions);
  ModelOffset result;
  for (int k = 0; k < 3; ++k) result.offsetMm[k] = solution.offsetMm[k];
  result.converged = solution.converged;
  result.clampedAxes = solution.clampedAxes;
  return result;
}

}  // namespace volcomp::loop
