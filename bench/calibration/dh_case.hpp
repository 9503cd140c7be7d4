#pragma once
// A D-H chain fit for the benchmarks: Bulla Ramos et al.'s Cartesian table
// (config/examples/cartesian-table-dh.json) with offsets on the a of its first two links, 100
// points (5 x 5 x 4 joint values), 0.1 um of noise; four deviations identified with
// Levenberg-Marquardt (tests/calibration/dh_identification_test.cpp,
// DeviationsRecoveredWithinThreeSigma).

#include <memory>

#include <nlohmann/json.hpp>

#include "dh_synthetic.hpp"
#include "volcomp/calibration/identification.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::bench {

struct DhCase {
  std::unique_ptr<calibration::IdentificationProblem> problem;
};

inline const DhCase& dhCase() {
  static const DhCase c = [] {
    const nlohmann::json truth = calibration::testing::seedChain();
    const calibration::MeasurementSet set = calibration::testing::simulateChain(truth, 1e-4, 5);
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
