// Calibration templates (ParseOptions::allowIdentify): "identify" blocks are collected by key
// path and the spec gets their "start" values.

#include <gtest/gtest.h>

#include <numbers>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

using model::Axis;
using model::motionIndex;
using model::MotionKind;

ParseOptions templates() {
  ParseOptions options;
  options.allowIdentify = true;
  return options;
}

TEST(ModelFileIdentify, ComponentsAreCollectedWithTheirStartValues) {
  const ModelDocument doc = parseModel(nlohmann::json::parse(R"({
    "format": "volcomp-model/1", "topology": "XYFZ", "error_units": {"length": "um", "angle": "urad"},
    "components": {
      "EXX": {"identify": {"kind": "table", "positions": [0, 100, 200]}},
      "EBX": {"identify": {"kind": "polynomial", "degree": 2}, "start": {"polynomial": [1, 2]}},
      "EC0Y": {"identify": true, "start": 10},
      "EYY": 4
    }})"),
                                       "template.json", templates());
  ASSERT_EQ(doc.identify.size(), 3u);
  EXPECT_EQ(doc.identify.at("components.EXX")["kind"], "table");
  EXPECT_EQ(doc.identify.at("components.EBX")["degree"], 2);
  EXPECT_EQ(doc.identify.at("components.EC0Y"), true);
  const auto& spec = std::get<model::MachineModelSpec>(doc.spec);
  EXPECT_EQ(std::get<double>(spec.motion[motionIndex(Axis::X, MotionKind::EX)]), 0.0);
  // The start value is in the file's units like any other component.
  const auto& ebx =
      std::get<model::PolynomialSpec>(spec.motion[motionIndex(Axis::X, MotionKind::EB)]);
  EXPECT_DOUBLE_EQ(ebx.coefficients[1], 2e-6);
  EXPECT_DOUBLE_EQ(spec.locationRad[model::locationIndex(Axis::Y, 2)], 10e-6);
  EXPECT_DOUBLE_EQ(std::get<double>(spec.motion[motionIndex(Axis::Y, MotionKind::EY)]), 4e-3);
}

TEST(ModelFileIdentify, ChainDeviations) {
  const ModelDocument doc = parseModel(nlohmann::json::parse(R"({
    "format": "volcomp-model/1", "chain": {"links": [
      {"joint": "prismatic", "theta": 0, "d": 0, "a": 0, "alpha": 90},
      {"joint": "prismatic", "theta": 90, "d": 0, "a": 0, "alpha": -90,
       "dalpha": {"identify": {}, "start": 0.001}, "dd": {"identify": {}}},
      {"joint": "fixed", "drotation_deg": {"identify": {"axes": "Y"}, "start": [0, 0.002, 0]}}]}})"),
                                       "chain-template.json", templates());
  ASSERT_EQ(doc.identify.size(), 3u);
  EXPECT_TRUE(doc.identify.count("chain.links[1].dalpha"));
  EXPECT_TRUE(doc.identify.count("chain.links[1].dd"));
  EXPECT_EQ(doc.identify.at("chain.links[2].drotation_deg")["axes"], "Y");
  const auto& chain = std::get<model::DhChainSpec>(doc.spec);
  EXPECT_DOUBLE_EQ(chain.links[1].dAlphaRad, 0.001 * std::numbers::pi / 180.0);
  EXPECT_EQ(chain.links[1].dDMm, 0.0);
  EXPECT_DOUBLE_EQ(chain.links[2].dRotationRad.y(), 0.002 * std::numbers::pi / 180.0);
}

TEST(ModelFileIdentify, IdentifyBlocksAcceptOnlyStart) {
  try {
    parseModel(nlohmann::json::parse(R"({"format": "volcomp-model/1", "topology": "FXYZ",
      "components": {"EXX": {"identify": {}, "begin": 1}}})"),
               "t.json", templates());
    ADD_FAILURE();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.keyPath(), "components.EXX.begin");
    EXPECT_NE(e.message().find("expected one of: identify, start"), std::string::npos);
  }
}

TEST(ModelFileIdentify, PlainModelsHaveNoIdentifyBlocks) {
  const ModelDocument doc = parseModel(
      nlohmann::json::parse(
          R"({"format": "volcomp-model/1", "topology": "FXYZ", "components": {"EXX": 1}})"),
      "m.json", templates());
  EXPECT_TRUE(doc.identify.empty());
}

}  // namespace
}  // namespace volcomp::config
