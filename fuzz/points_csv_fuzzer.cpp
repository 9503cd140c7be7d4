// The points CSV of `volcomp eval --points`: header x,y,z, rows of three finite numbers, each
// evaluated and solved with the example VMC model as the verb does.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "points_csv.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {

const volcomp::model::MachineModel& exampleModel() {
  static const volcomp::model::MachineModel model(std::get<volcomp::model::MachineModelSpec>(
      volcomp::config::loadModelFile(VOLCOMP_EXAMPLES_DIR "/vmc-xyfz-21.json").spec));
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  const model::MachineModel& model = exampleModel();
  std::istringstream in{std::string(fuzz::text(data, size))};
  try {
    cli::PointsCsvReader reader(in, "fuzz.csv");
    model::Workspace ws;
    Eigen::Vector3d q;
    while (reader.next(q)) {
      fuzz::require(q.allFinite(), "a point is not finite");
      model::evaluate(model, ws, q);
      model::solveOffset(model, ws, q);
    }
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
