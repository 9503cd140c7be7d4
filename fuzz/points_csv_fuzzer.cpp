// The points CSV of `volcomp eval --points` through the shared reader (config::CsvReader with the
// verb's schema): every row read has finite coordinates (and tool), and is evaluated and solved
// with the example VMC model as the verb does.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "points_csv.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {

const volcomp::model::MachineModel& exampleModel() {
  static const volcomp::model::MachineModel model(std::get<volcomp::model::MachineModelSpec>(
      volcomp::config::loadModelFile(VOLCOMP_EXAMPLES_DIR + "/vmc-xyfz-21.json").spec));
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  const model::MachineModel& model = exampleModel();
  std::istringstream in{std::string(fuzz::text(data, size))};
  try {
    config::CsvReader reader(in, "fuzz.csv", cli::pointsSchema());
    const int tx = reader.column("tx"), direction = reader.column("direction");
    model::Workspace ws;
    while (reader.next()) {
      const Eigen::Vector3d q(reader.number("x"), reader.number("y"), reader.number("z"));
      fuzz::require(q.allFinite(), "a point is not finite");
      if (tx >= 0) {
        const Eigen::Vector3d tool(reader.number(tx), reader.number("ty"), reader.number("tz"));
        fuzz::require(tool.allFinite(), "a tool is not finite");
      }
      const model::Directions d =
          direction >= 0 ? reader.directions(direction) : model::Directions{};
      model::evaluate(model, ws, q, d);
      model::solveOffset(model, ws, q, d);
    }
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
