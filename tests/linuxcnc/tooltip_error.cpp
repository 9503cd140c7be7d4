// volcomp-tooltip-error: the true tool-tip error along a recorded path, with and without the
// offsets that were applied (for the LinuxCNC tests, which record LinuxCNC's commanded axis
// positions and applied external offsets every servo period).
//
//   volcomp-tooltip-error TRUE_MODEL.json RECORD.csv
//
// RECORD.csv: header x,y,z,ox,oy,oz (mm), one row per sample in time order: commanded positions q
// and the external offsets o LinuxCNC applied (its axes then stand at q + o). With E_true the
// error of the true model (model.md: E = p - p0), the tool tip misses the programmed point by
//   uncompensated  E_true(q)
//   compensated    p_true(q + o) - p0(q) = E_true(q + o) + o
// (as volcomp-sim reports it), evaluated with the direction each axis last moved (hysteresis
// 2 um, as the daemon's direction tracker) for bidirectional tables. Prints one JSON object:
// samples, rms/max of the 3-D error un/compensated (um), per axis (um). Exit 2 on bad input.

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <variant>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/loop/direction_tracker.hpp"
#include "volcomp/model/machine_model.hpp"

namespace {

struct Stats {
  double sumSq = 0.0;
  double max = 0.0;
  Eigen::Vector3d sumSqAxis = Eigen::Vector3d::Zero();
  Eigen::Vector3d maxAxis = Eigen::Vector3d::Zero();
  void add(const Eigen::Vector3d& e) {
    sumSq += e.squaredNorm();
    max = std::max(max, e.norm());
    sumSqAxis += e.cwiseAbs2();
    maxAxis = maxAxis.cwiseMax(e.cwiseAbs());
  }
};

double rmsUm(double sumSq, long n) {
  return n > 0 ? std::sqrt(sumSq / static_cast<double>(n)) * 1000.0 : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: volcomp-tooltip-error TRUE_MODEL.json RECORD.csv\n";
    return 2;
  }
  try {
    volcomp::config::ModelDocument doc = volcomp::config::loadModelFile(argv[1]);
    auto* spec = std::get_if<volcomp::model::MachineModelSpec>(&doc.spec);
    if (spec == nullptr) {
      std::cerr << argv[1] << ": a 3-axis machine model is needed\n";
      return 2;
    }
    const volcomp::model::MachineModel model(*spec);
    volcomp::model::Workspace ws;
    volcomp::loop::DirectionTracker tracker(0.002);

    std::ifstream in(argv[2]);
    if (!in) {
      std::cerr << argv[2] << ": cannot read\n";
      return 2;
    }
    std::string line;
    std::getline(in, line);
    if (line != "x,y,z,ox,oy,oz") {
      std::cerr << argv[2] << ":1: expected the header x,y,z,ox,oy,oz\n";
      return 2;
    }
    Stats uncompensated, compensated;
    long n = 0, lineNo = 1;
    while (std::getline(in, line)) {
      ++lineNo;
      std::istringstream row(line);
      std::array<double, 6> v{};
      char comma = 0;
      for (std::size_t i = 0; i < 6; ++i) {
        if (!(row >> v[i]) || (i < 5 && !(row >> comma && comma == ','))) {
          std::cerr << argv[2] << ":" << lineNo << ": expected six numbers\n";
          return 2;
        }
      }
      const Eigen::Vector3d q(v[0], v[1], v[2]);
      const Eigen::Vector3d o(v[3], v[4], v[5]);
      const auto& directions = tracker.update({v[0], v[1], v[2]});
      uncompensated.add(volcomp::model::evaluate(model, ws, q, directions).errorMm);
      compensated.add(volcomp::model::evaluate(model, ws, q + o, directions).errorMm + o);
      ++n;
    }
    nlohmann::json axes;
    const char* names[] = {"X", "Y", "Z"};
    for (int k = 0; k < 3; ++k) {
      axes[names[k]] = {{"rms_uncompensated_um", rmsUm(uncompensated.sumSqAxis[k], n)},
                        {"rms_compensated_um", rmsUm(compensated.sumSqAxis[k], n)},
                        {"max_uncompensated_um", uncompensated.maxAxis[k] * 1000.0},
                        {"max_compensated_um", compensated.maxAxis[k] * 1000.0}};
    }
    const nlohmann::json out = {{"samples", n},
                                {"rms_uncompensated_um", rmsUm(uncompensated.sumSq, n)},
                                {"rms_compensated_um", rmsUm(compensated.sumSq, n)},
                                {"max_uncompensated_um", uncompensated.max * 1000.0},
                                {"max_compensated_um", compensated.max * 1000.0},
                                {"axes", axes}};
    std::cout << out.dump() << "\n";
    return 0;
  } catch (const volcomp::config::ConfigError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << argv[1] << ": " << e.what() << "\n";
    return 2;
  }
}
