#include <numbers>
#include <utility>

#include "model_file_parts.hpp"

namespace volcomp::config::detail {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// A deviation is a number or, in a calibration template, {"identify": ..., "start": number}.
double readDeviation(const JsonReader& node, double factor, const Context& ctx) {
  if (const auto block = readIdentifyBlock(node, ctx.options, ctx.doc)) {
    return block->start ? block->start->number() * factor : 0.0;
  }
  if (!node.isNumber()) node.failExpected("a number");
  return node.number() * factor;
}

Eigen::Vector3d readTriple(const JsonReader& node, double factor, const std::string& expected) {
  if (!node.isArray() || node.size() != 3) node.failExpected(expected);
  const auto v = node.fixedNumbers<3>();
  return Eigen::Vector3d(v[0], v[1], v[2]) * factor;
}

Eigen::Vector3d readDeviationTriple(const JsonReader& node, double factor,
                                    const std::string& expected, const Context& ctx) {
  if (const auto block = readIdentifyBlock(node, ctx.options, ctx.doc)) {
    return block->start ? readTriple(*block->start, factor, expected) : Eigen::Vector3d::Zero();
  }
  return readTriple(node, factor, expected);
}

model::DhLinkSpec readLink(const JsonReader& node, const Context& ctx) {
  node.expectObject();
  model::DhLinkSpec link;
  const JsonReader joint = node.at("joint");
  const std::string type = joint.oneOf({"prismatic", "revolute", "fixed"});
  link.joint = type == "prismatic"  ? model::JointType::Prismatic
               : type == "revolute" ? model::JointType::Revolute
                                    : model::JointType::Fixed;
  link.isTransform = node.has("rotation_deg") || node.has("translation") ||
                     node.has("drotation_deg") || node.has("dtranslation");
  if (link.isTransform) {
    node.allowOnly({"joint", "rotation_deg", "translation", "drotation_deg", "dtranslation"});
    if (link.joint != model::JointType::Fixed) {
      joint.failExpected("\"fixed\" for a transform link (rotation_deg / translation)");
    }
    const std::string angles = "[rx, ry, rz] in degrees";
    const std::string lengths = "[x, y, z] in mm";
    if (const auto r = node.find("rotation_deg"))
      link.rotationRad = readTriple(*r, kDegToRad, angles);
    if (const auto t = node.find("translation")) link.translationMm = readTriple(*t, 1.0, lengths);
    if (const auto r = node.find("drotation_deg")) {
      link.dRotationRad = readDeviationTriple(*r, kDegToRad, angles, ctx);
    }
    if (const auto t = node.find("dtranslation")) {
      link.dTranslationMm = readDeviationTriple(*t, 1.0, lengths, ctx);
    }
    return link;
  }
  node.allowOnly({"joint", "theta", "d", "a", "alpha", "dtheta", "dd", "da", "dalpha"});
  link.thetaRad = node.at("theta").number() * kDegToRad;
  link.dMm = node.at("d").number();
  link.aMm = node.at("a").number();
  link.alphaRad = node.at("alpha").number() * kDegToRad;
  if (const auto v = node.find("dtheta")) link.dThetaRad = readDeviation(*v, kDegToRad, ctx);
  if (const auto v = node.find("dd")) link.dDMm = readDeviation(*v, 1.0, ctx);
  if (const auto v = node.find("da")) link.dAMm = readDeviation(*v, 1.0, ctx);
  if (const auto v = node.find("dalpha")) link.dAlphaRad = readDeviation(*v, kDegToRad, ctx);
  return link;
}

}  // namespace

void parseChainDocument(const JsonReader& root, const ParseOptions& options, ModelDocument& doc) {
  root.allowOnly({"format", "name", "description", "chain", "calibration"});
  const Context ctx{options, doc};
  model::DhChainSpec spec;
  spec.name = root.stringOr("name", "");
  if (const auto description = root.find("description")) description->string();
  const JsonReader chain = root.at("chain");
  chain.allowOnly({"convention", "links"});
  if (const auto convention = chain.find("convention")) {
    spec.convention = convention->oneOf({"dh", "mdh"}) == "mdh" ? model::DhConvention::Modified
                                                                : model::DhConvention::Standard;
  }
  for (const JsonReader& link : chain.at("links").elements(1)) {
    spec.links.push_back(readLink(link, ctx));
  }
  if (const auto calibration = root.find("calibration")) {
    doc.calibration = readCalibrationRecord(*calibration);
  }
  // The chain block states its own units (degrees, mm), whatever error_units would say.
  doc.units = {LengthUnit::Millimetre, AngleUnit::Degree};
  doc.spec = std::move(spec);
}

}  // namespace volcomp::config::detail
