#pragma once
// Bulla Ramos et al.'s Cartesian table as a D-H chain and measurements simulated on it, shared by
// the D-H identification tests and the benchmark.

#include <random>

#include <nlohmann/json.hpp>

#include "random_draws.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/dh_chain.hpp"

namespace volcomp::calibration::testing {

// Bulla Ramos et al.'s chain (config/examples/cartesian-table-dh.json) with its perpendicularity
// deviations plus offsets on the a of the first two links.
inline nlohmann::json seedChain() {
  return nlohmann::json::parse(R"({
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
}

inline MeasurementSet simulateChain(const nlohmann::json& truth, double noiseMm, unsigned seed) {
  const model::DhChain chain(std::get<model::DhChainSpec>(config::parseModel(truth, "t").spec));
  std::mt19937 generator(seed);
  std::normal_distribution<double> noise(0.0, noiseMm);
  MeasurementSet set;
  set.file = "chain.csv";
  int line = 2;
  for (double x : {0.0, 75.0, 150.0, 225.0, 300.0}) {
    for (double y : {0.0, 50.0, 100.0, 150.0, 200.0}) {
      for (double z : {0.0, 33.0, 66.0, 100.0}) {
        Measurement m;
        m.qMm = {x, y, z};
        m.errorMm = chain.evaluate(m.qMm.data()).errorMm;
        if (noiseMm > 0) m.errorMm += testutil::draw3(noise, generator);
        m.line = line++;
        set.points.push_back(m);
      }
    }
  }
  return set;
}

}  // namespace volcomp::calibration::testing
