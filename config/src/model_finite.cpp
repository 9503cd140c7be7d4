#include "volcomp/config/model_finite.hpp"

#include <array>
#include <cmath>
#include <string>
#include <variant>
#include <vector>

#include "volcomp/config/config_error.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/model/dh_chain.hpp"
#include "volcomp/model/machine_model.hpp"

namespace volcomp::config {
namespace {

constexpr int kSamplesPerAxis = 201;

bool finite(const Eigen::Vector3d& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

std::string position(const Eigen::Vector3d& q) {
  return "X " + format::general(q.x()) + ", Y " + format::general(q.y()) + ", Z " +
         format::general(q.z()) + " mm";
}

// The values an axis takes in the check: its travel's ends and middle, or 0 without a travel.
std::vector<double> stations(const std::optional<std::array<double, 2>>& travel) {
  if (!travel) return {0.0};
  return {(*travel)[0], 0.5 * ((*travel)[0] + (*travel)[1]), (*travel)[1]};
}

void checkMachine(const ModelDocument& doc, const model::MachineModelSpec& spec) {
  const model::MachineModel machine(spec);
  model::Workspace ws;
  const auto fail = [&](const Eigen::Vector3d& q) {
    std::string key = spec.grids.empty() ? "components" : "grids";
    for (int i = 0; i < 18; ++i) {
      if (!std::isfinite(ws.motion[static_cast<std::size_t>(i)])) {
        key = "components." + model::motionName(i);
        break;
      }
    }
    throw ConfigError(doc.file, key,
                      "the model's error is not finite at " + position(q) +
                          " (a coefficient or value too large for the travel?); refused");
  };
  for (int axis = 0; axis < 3; ++axis) {
    const auto& travel = spec.travelMm[static_cast<std::size_t>(axis)];
    const int samples = travel ? kSamplesPerAxis : 1;
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    for (double qa : stations(spec.travelMm[static_cast<std::size_t>(a)])) {
      for (double qb : stations(spec.travelMm[static_cast<std::size_t>(b)])) {
        for (int i = 0; i < samples; ++i) {
          Eigen::Vector3d q;
          q[axis] = travel ? (*travel)[0] + ((*travel)[1] - (*travel)[0]) * i / (samples - 1) : 0.0;
          q[a] = qa;
          q[b] = qb;
          for (const int direction : {1, -1}) {
            model::Directions directions;
            directions.fill(direction > 0 ? model::Direction::Positive
                                          : model::Direction::Negative);
            const model::PointError e = model::evaluate(machine, ws, q, directions);
            if (!finite(e.errorMm) || !finite(e.angularErrorRad)) fail(q);
          }
        }
      }
    }
  }
}

void checkChain(const ModelDocument& doc, const model::DhChainSpec& spec) {
  const model::DhChain chain(spec);
  const std::vector<double> joints(static_cast<std::size_t>(chain.jointCount()), 0.0);
  const model::DhResult r = chain.evaluate(joints.data());
  if (!finite(r.errorMm) || !finite(r.angularErrorRad)) {
    throw ConfigError(doc.file, "chain",
                      "the chain's error is not finite at every joint value 0 (a value too "
                      "large?); refused");
  }
}

}  // namespace

void checkModelFinite(const ModelDocument& doc) {
  if (const auto* spec = std::get_if<model::MachineModelSpec>(&doc.spec)) {
    checkMachine(doc, *spec);
  } else {
    checkChain(doc, std::get<model::DhChainSpec>(doc.spec));
  }
}

}  // namespace volcomp::config
