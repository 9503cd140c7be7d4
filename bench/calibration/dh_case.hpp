#pragma once
// A D-H chain fit for the benchmarks: Bulla Ramos et al.'s Cartesian table
// (config/examples/cartesian-table-dh.json) with offsets on the a of its first two links, 100
// points (5 x 5 x 4 joint values), 0.1 um of noise; four deviations identified with
// Levenberg-Marquardt (tests/calibration/dh_identification_test.cpp,
// DeviationsRecoveredWithinThreeSigma).

#include <memory>
#include <random>

#include <nlohmann/json.hpp>

#include "random_draws.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"

namespace volcomp::bench {

struct DhCase {
  std::unique_ptr<calibration::IdentificationProblem> problem;
};

inline const DhCase& dhCase() {
  static const DhCase c = [] {
    const nlohmann::json truth = nlohmann::json::parse(R"({
      "format": "volcomp-model/1",
      "chain": {"convention": "dh", "links": [
        {"joint": "prismatic", "theta": 0, "d": 0, "a": 120, "alpha": 90, "da": 0.012},
        {"joint": "prismatic", "theta": 90, "d": 0, "a": 85, "alpha": -90, "dalpha": -0.0013544,
         "da": -0.008},
        {"joint": "prismatic", "theta": 0, "d": 50, "a": 40, "alpha": 0, "dalpha": 0.0010835},
        {"joint": "fixed", "rotation_deg": [0, 0, 0], "translation": [0, 0, 0],
         "drotation_deg": [0, 0.0010835, 0]},
        {"joint": "fixed", "theta": 0, "d": 150, "a": 30, "alpha": 0}
      ]}})");
    const model::DhChain chain(std::get<model::DhChainSpec>(config::parseModel(truth, "t").spec));
    std::mt19937 generator(5);
    std::normal_distribution<double> noise(0.0, 1e-4);
    calibration::MeasurementSet set;
    set.file = "chain.csv";
    int line = 2;
    for (double x : {0.0, 75.0, 150.0, 225.0, 300.0}) {
      for (double y : {0.0, 50.0, 100.0, 150.0, 200.0}) {
        for (double z : {0.0, 33.0, 66.0, 100.0}) {
          calibration::Measurement m;
          m.qMm = {x, y, z};
          m.errorMm = chain.evaluate(m.qMm.data()).errorMm + testutil::draw3(noise, generator);
          m.line = line++;
          set.points.push_back(m);
        }
      }
    }
    nlohmann::json t = truth;
    auto& links = t["chain"]["links"];
    links[0]["da"] = {{"identify", "constant"}};
    links[1]["dalpha"] = {{"identify", "constant"}};
    links[2]["dalpha"] = {{"identify", "constant"}, {"start", 0.0}};
    links[1]["da"] = {{"identify", "constant"}};
    config::ParseOptions options;
    options.allowIdentify = true;
    DhCase out;
    out.problem = calibration::makeIdentificationProblem(
        config::parseModel(t, "chain-template.json", options), set);
    return out;
  }();
  return c;
}

}  // namespace volcomp::bench
