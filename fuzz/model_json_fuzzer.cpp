// Model files (volcomp-model/1 JSON): text -> JSON -> model spec (plain and calibration-template
// forms) -> the immutable model, evaluated and solved at a few points; a 3-axis spec is written
// back and must read again (writeModel's round-trip promise).

#include <array>
#include <cstddef>
#include <cstdint>
#include <variant>
#include <vector>

#include "fuzz_support.hpp"
#include "volcomp/config/json_reader.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {

using namespace volcomp;

void exercise(const model::MachineModelSpec& spec, const config::ErrorUnits& units) {
  const model::MachineModel machine(spec);
  model::Workspace ws;
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero(), Eigen::Vector3d(1e4, -1e4, 3.5)};
  Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (spec.travelMm[k]) {
      low[k] = (*spec.travelMm[k])[0];
      high[k] = (*spec.travelMm[k])[1];
    }
  }
  points.push_back(low);
  points.push_back(high);
  points.push_back(0.5 * (low + high));
  for (const Eigen::Vector3d& q : points) {
    for (const model::Direction d :
         {model::Direction::Unknown, model::Direction::Positive, model::Direction::Negative}) {
      const model::Directions directions{d, d, d};
      model::evaluate(machine, ws, q, directions, model::EvalMode::Exact);
      model::evaluate(machine, ws, q, directions, model::EvalMode::FirstOrder);
      model::solveOffset(machine, ws, q, directions);
    }
  }
  std::array<model::PointError, 5> batch;
  model::evaluateBatch(machine, ws, points, batch);
  // What the writer writes, the reader must read.
  const nlohmann::json written = config::writeModel(spec, units);
  try {
    config::parseModel(written, "written.json");
  } catch (const config::ConfigError& e) {
    volcomp::fuzz::finding("writeModel wrote a model parseModel refuses", e.what());
  }
}

void exercise(const model::DhChainSpec& spec) {
  const model::DhChain chain(spec);
  std::vector<double> joints(static_cast<std::size_t>(chain.jointCount()), 0.0);
  chain.evaluate(joints.data());
  for (double& j : joints) j = 100.0;
  chain.evaluate(joints.data());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  try {
    const nlohmann::json document = config::parseJsonText(fuzz::text(data, size), "fuzz.json");
    for (const bool identify : {false, true}) {
      config::ParseOptions options;
      options.allowIdentify = identify;
      try {
        const config::ModelDocument doc = config::parseModel(document, "fuzz.json", options);
        if (const auto* machine = std::get_if<model::MachineModelSpec>(&doc.spec)) {
          // A template's identify blocks are not part of the spec it returns; only plain models
          // promise the round trip.
          if (doc.identify.empty()) {
            exercise(*machine, doc.units);
          } else {
            model::MachineModel built(*machine);
          }
        } else {
          exercise(std::get<model::DhChainSpec>(doc.spec));
        }
      } catch (const config::ConfigError& e) {
        fuzz::checkMessage(e);
      } catch (const model::ModelError& e) {
        fuzz::checkMessage(e);
      }
    }
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
