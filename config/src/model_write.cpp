#include <numbers>

#include "model_file_parts.hpp"

namespace volcomp::config {
namespace {

using Json = nlohmann::json;

constexpr const char* kAxisNames[3] = {"X", "Y", "Z"};
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

Json scaledArray(const std::vector<double>& values, double factor) {
  Json out = Json::array();
  for (double v : values) out.push_back(v / factor);
  return out;
}

Json vector3(const Eigen::Vector3d& v, double factor = 1.0) {
  return Json::array({v.x() * factor, v.y() * factor, v.z() * factor});
}

// nullopt for the zero constant, which the format expresses by leaving the component out.
std::optional<Json> writeFunction(const model::ErrorFunctionSpec& spec, double factor) {
  if (const double* constant = std::get_if<double>(&spec)) {
    if (*constant == 0.0) return std::nullopt;
    return Json(*constant / factor);
  }
  if (const auto* polynomial = std::get_if<model::PolynomialSpec>(&spec)) {
    return Json{{"polynomial", scaledArray(polynomial->coefficients, factor)}};
  }
  const auto& table = std::get<model::TableSpec>(spec);
  Json out{{"positions", scaledArray(table.positionsMm, 1.0)},
           {"values", scaledArray(table.values, factor)},
           {"interpolation", interpolationName(table.interpolation)}};
  if (!table.valuesNegative.empty()) {
    out["values_negative"] = scaledArray(table.valuesNegative, factor);
  }
  return out;
}

Json writeGridValues(const model::GridSpec& grid, std::size_t level, std::size_t offset,
                     double factor) {
  Json out = Json::array();
  std::size_t stride = 1;
  for (std::size_t l = level + 1; l < grid.axesMm.size(); ++l) stride *= grid.axesMm[l].size();
  for (std::size_t i = 0; i < grid.axesMm[level].size(); ++i) {
    if (level + 1 == grid.axesMm.size()) {
      out.push_back(grid.valuesMm.at(offset + i) / factor);
    } else {
      out.push_back(writeGridValues(grid, level + 1, offset + i * stride, factor));
    }
  }
  return out;
}

}  // namespace

const char* interpolationName(model::Interpolation interpolation) noexcept {
  switch (interpolation) {
    case model::Interpolation::Quadratic:
      return "quadratic";
    case model::Interpolation::Cubic:
      return "cubic";
    case model::Interpolation::Linear:
      break;
  }
  return "linear";
}

nlohmann::json writeModel(const model::MachineModelSpec& spec, const ErrorUnits& units) {
  const double lengthToMm = units.lengthToMm();
  const double angleToRad = units.angleToRad();
  Json out{{"format", "volcomp-model/1"}, {"topology", spec.topology}};
  if (!spec.name.empty()) out["name"] = spec.name;
  Json travel = Json::object();
  for (int axis = 0; axis < 3; ++axis) {
    if (spec.travelMm[axis]) {
      travel[kAxisNames[axis]] =
          Json::array({(*spec.travelMm[axis])[0], (*spec.travelMm[axis])[1]});
    }
  }
  if (!travel.empty()) out["travel"] = travel;
  out["tool"] = vector3(spec.toolMm);
  out["workpiece"] = vector3(spec.workpieceMm);
  out["error_units"] = Json{{"length", unitName(units.length)}, {"angle", unitName(units.angle)}};
  Json components = Json::object();
  for (int i = 0; i < 18; ++i) {
    const double factor = i % 6 < 3 ? lengthToMm : angleToRad;
    if (auto f = writeFunction(spec.motion[i], factor)) components[detail::motionNames()[i]] = *f;
  }
  for (int i = 0; i < 9; ++i) {
    if (spec.locationRad[i] != 0.0) {
      components[detail::locationNames()[i]] = spec.locationRad[i] / angleToRad;
    }
  }
  out["components"] = components;
  Json grids = Json::array();
  for (const model::GridSpec& grid : spec.grids) {
    Json g{{"component", grid.component == 0 ? "EX" : grid.component == 1 ? "EY" : "EZ"}};
    Json over = Json::array();
    Json axes = Json::object();
    for (std::size_t l = 0; l < grid.over.size(); ++l) {
      const char* name = kAxisNames[static_cast<int>(grid.over[l])];
      over.push_back(name);
      axes[name] = scaledArray(grid.axesMm.at(l), 1.0);
    }
    g["over"] = over;
    g["axes"] = axes;
    g["values"] = writeGridValues(grid, 0, 0, lengthToMm);
    grids.push_back(g);
  }
  out["grids"] = grids;
  return out;
}

nlohmann::json writeModel(const model::DhChainSpec& spec) {
  Json links = Json::array();
  for (const model::DhLinkSpec& link : spec.links) {
    Json l{{"joint", link.joint == model::JointType::Prismatic  ? "prismatic"
                     : link.joint == model::JointType::Revolute ? "revolute"
                                                                : "fixed"}};
    if (link.isTransform) {
      l["rotation_deg"] = vector3(link.rotationRad, kRadToDeg);
      l["translation"] = vector3(link.translationMm);
      if (!link.dRotationRad.isZero(0.0))
        l["drotation_deg"] = vector3(link.dRotationRad, kRadToDeg);
      if (!link.dTranslationMm.isZero(0.0)) l["dtranslation"] = vector3(link.dTranslationMm);
    } else {
      l["theta"] = link.thetaRad * kRadToDeg;
      l["d"] = link.dMm;
      l["a"] = link.aMm;
      l["alpha"] = link.alphaRad * kRadToDeg;
      if (link.dThetaRad != 0.0) l["dtheta"] = link.dThetaRad * kRadToDeg;
      if (link.dDMm != 0.0) l["dd"] = link.dDMm;
      if (link.dAMm != 0.0) l["da"] = link.dAMm;
      if (link.dAlphaRad != 0.0) l["dalpha"] = link.dAlphaRad * kRadToDeg;
    }
    links.push_back(l);
  }
  Json out{{"format", "volcomp-model/1"},
           {"chain",
            {{"convention", spec.convention == model::DhConvention::Modified ? "mdh" : "dh"},
             {"links", links}}}};
  if (!spec.name.empty()) out["name"] = spec.name;
  return out;
}

}  // namespace volcomp::config
