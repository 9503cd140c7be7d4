#include <memory>
#include <utility>

#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"
#include "volcomp/sim/sim_config.hpp"

namespace volcomp::sim {

ErrorFunction loadTrueError(const std::string& modelFile, Travel* travel) {
  model::MachineModelSpec spec = config::loadMachineModelFile(modelFile, "the simulated machine");
  if (travel != nullptr) *travel = spec.travelMm;
  // loadMachineModelFile has built the model once already: this cannot throw ModelError.
  auto machineModel = std::make_shared<const model::MachineModel>(std::move(spec));
  // One workspace per machine: the Machine calls this under its own mutex.
  auto ws = std::make_shared<model::Workspace>();
  return [machineModel, ws](const Vec3& q, const MotionDirections& moved) {
    model::Directions directions{};
    for (std::size_t k = 0; k < 3; ++k) {
      directions[k] = moved[k] > 0   ? model::Direction::Positive
                      : moved[k] < 0 ? model::Direction::Negative
                                     : model::Direction::Unknown;
    }
    const model::PointError e =
        model::evaluate(*machineModel, *ws, Eigen::Vector3d(q[0], q[1], q[2]), directions);
    return Vec3{e.errorMm.x(), e.errorMm.y(), e.errorMm.z()};
  };
}

}  // namespace volcomp::sim
