#pragma once
// The 21-component identification case shared by bench_calibration and
// calibration_instruction_count: an XYFZ machine whose 18 motion errors are 8-node linear tables
// and 3 squareness constants (147 parameters), "measured" at 1000 positions (10 x 10 x 10 over
// the travel) with 5 tools and 1 um of noise: 5000 points, 15000 rows.

#include <algorithm>
#include <random>
#include <vector>

#include "synthetic.hpp"
#include "volcomp/calibration/identification.hpp"

namespace volcomp::bench {

using nlohmann::json;
namespace testing = calibration::testing;

inline json vmcTruth() {
  json components = json::object();
  const std::vector<double> positions{0, 100, 200, 300, 400, 500, 600, 700};
  std::mt19937 generator(21);
  std::normal_distribution<double> value(0.0, 5.0);
  for (int i = 0; i < 18; ++i) {
    std::vector<double> values;
    for (std::size_t j = 0; j < positions.size(); ++j) values.push_back(value(generator));
    const int axis = i / 6;
    std::vector<double> scaled = positions;
    for (double& p : scaled)
      p = axis == 2 ? -p * 4.0 / 7.0 : p * (axis == 1 ? 5.0 / 7.0 : 8.0 / 7.0);
    if (axis == 2) std::reverse(scaled.begin(), scaled.end());
    components[model::motionName(i)] = {
        {"positions", scaled}, {"values", values}, {"interpolation", "linear"}};
  }
  components["EC0Y"] = 12.0;
  components["EB0Z"] = -8.0;
  components["EA0Z"] = 5.0;
  return json{{"format", "volcomp-model/1"},
              {"topology", "XYFZ"},
              {"tool", {0, 0, 100}},
              {"error_units", {{"length", "um"}, {"angle", "urad"}}},
              {"components", components}};
}

inline json vmcTemplate(const json& truth) {
  json t = truth;
  for (auto& [name, component] : t["components"].items()) {
    if (name.size() == 4) {
      component = {{"identify", "constant"}};
    } else {
      component = {{"identify",
                    {{"basis", "table"},
                     {"positions", component["positions"]},
                     {"interpolation", "linear"}}}};
    }
  }
  return t;
}

struct VmcCase {
  config::ModelDocument document;
  calibration::MeasurementSet data;
};

inline const VmcCase& vmcCase() {
  static const VmcCase instance = [] {
    const json truth = vmcTruth();
    testing::SyntheticOptions options;
    options.x.clear();
    options.y.clear();
    options.z.clear();
    for (int i = 0; i < 10; ++i) {
      options.x.push_back(800.0 * i / 9.0);
      options.y.push_back(500.0 * i / 9.0);
      options.z.push_back(-400.0 * i / 9.0);
    }
    options.tools = {Eigen::Vector3d(0, 0, 100), Eigen::Vector3d(0, 0, 250),
                     Eigen::Vector3d(150, 0, 150), Eigen::Vector3d(0, 150, 150),
                     Eigen::Vector3d(-100, -100, 200)};
    options.noiseMm = 1e-3;
    return VmcCase{testing::templateDocument(vmcTemplate(truth)),
                   testing::simulate(testing::machineSpec(truth), options)};
  }();
  return instance;
}

}  // namespace volcomp::bench
