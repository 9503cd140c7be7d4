#include <memory>
#include <variant>

#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"
#include "volcomp/sim/sim_config.hpp"

namespace volcomp::sim {

ErrorFunction loadTrueError(const std::string& modelFile, Travel* travel) {
  config::ModelDocument doc = config::loadModelFile(modelFile);
  auto* spec = std::get_if<model::MachineModelSpec>(&doc.spec);
  if (spec == nullptr) {
    throw config::ConfigError(modelFile, "",
                              "the simulator needs a 3-axis model (topology and components), not "
                              "a D-H chain");
  }
  if (travel != nullptr) *travel = spec->travelMm;
  std::shared_ptr<const model::MachineModel> machineModel;
  try {
    machineModel = std::make_shared<const model::MachineModel>(*spec);
  } catch (const model::ModelError& e) {
    throw config::ConfigError(modelFile, "", e.what());
  }
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
