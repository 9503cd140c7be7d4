#include "volcomp/daemon/compensation_model.hpp"

#include <utility>
#include <variant>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::daemon {

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

std::shared_ptr<CompensationModel> loadCompensationModel(const std::string& path) {
  config::ModelDocument document = config::loadModelFile(path);
  auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw config::ConfigError(path, "chain",
                              "the daemon compensates 3-axis machine models; a D-H chain file "
                              "cannot be used for live compensation");
  }
  std::string name = spec->name.empty() ? path : spec->name;
  return std::make_shared<MachineModelCompensation>(model::MachineModel(std::move(*spec)),
                                                    std::move(name));
}

}  // namespace volcomp::daemon
