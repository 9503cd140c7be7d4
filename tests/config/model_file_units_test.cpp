// error_units apply to error values only (constants, table values, polynomial coefficients,
// grid values, location errors); positions, travel, tool and workpiece stay mm.

#include <gtest/gtest.h>

#include <numbers>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

using model::Axis;
using model::motionIndex;
using model::MotionKind;

model::MachineModelSpec machineOf(const std::string& text) {
  const ModelDocument doc = parseModel(nlohmann::json::parse(text), "units.json");
  return std::get<model::MachineModelSpec>(doc.spec);
}

TEST(ModelFileUnits, DefaultsAreMillimetresAndRadians) {
  const ModelDocument doc = parseModel(
      nlohmann::json::parse(
          R"({"format": "volcomp-model/1", "topology": "FXYZ", "components": {"EXX": 0.5, "EBX": 0.25}})"),
      "units.json");
  EXPECT_EQ(doc.units.length, LengthUnit::Millimetre);
  EXPECT_EQ(doc.units.angle, AngleUnit::Radian);
  const auto& spec = std::get<model::MachineModelSpec>(doc.spec);
  EXPECT_EQ(std::get<double>(spec.motion[motionIndex(Axis::X, MotionKind::EX)]), 0.5);
  EXPECT_EQ(std::get<double>(spec.motion[motionIndex(Axis::X, MotionKind::EB)]), 0.25);
}

TEST(ModelFileUnits, MicrometresAndMicroradiansScaleErrorValuesOnly) {
  const auto spec = machineOf(R"({
    "format": "volcomp-model/1", "topology": "XYFZ",
    "travel": {"X": [0, 850]}, "tool": [0, 0, 120], "workpiece": [1, 2, 3],
    "error_units": {"length": "um", "angle": "urad"},
    "components": {
      "EXX": {"positions": [0, 100, 200], "values": [0, 4.1, 7.9], "values_negative": [1, 5, 9]},
      "EBX": {"polynomial": [2, 0.02, 0.0001]},
      "EYY": 3,
      "ECZ": {"positions": [-10, 0], "values": [5, -5], "interpolation": "cubic"},
      "EC0Y": 18.5
    },
    "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [0, 10], "Y": [0, 5]},
               "values": [[1, 2], [3, 4]]}]
  })");
  // Lengths: file value x 1e-3 mm/um; angles: file value x 1e-6 rad/urad.
  const auto& exx = std::get<model::TableSpec>(spec.motion[motionIndex(Axis::X, MotionKind::EX)]);
  EXPECT_EQ(exx.positionsMm, (std::vector<double>{0, 100, 200}));
  EXPECT_DOUBLE_EQ(exx.values[1], 4.1e-3);
  EXPECT_DOUBLE_EQ(exx.values[2], 7.9e-3);
  EXPECT_DOUBLE_EQ(exx.valuesNegative[2], 9e-3);
  EXPECT_EQ(exx.interpolation, model::Interpolation::Linear);
  // Every polynomial coefficient scales: c0 + c1 q + c2 q^2 all give error units.
  const auto& ebx =
      std::get<model::PolynomialSpec>(spec.motion[motionIndex(Axis::X, MotionKind::EB)]);
  ASSERT_EQ(ebx.coefficients.size(), 3u);
  EXPECT_DOUBLE_EQ(ebx.coefficients[0], 2e-6);
  EXPECT_DOUBLE_EQ(ebx.coefficients[1], 0.02e-6);
  EXPECT_DOUBLE_EQ(ebx.coefficients[2], 0.0001e-6);
  EXPECT_DOUBLE_EQ(std::get<double>(spec.motion[motionIndex(Axis::Y, MotionKind::EY)]), 3e-3);
  const auto& ecz = std::get<model::TableSpec>(spec.motion[motionIndex(Axis::Z, MotionKind::EC)]);
  EXPECT_EQ(ecz.positionsMm, (std::vector<double>{-10, 0}));
  EXPECT_DOUBLE_EQ(ecz.values[0], 5e-6);
  EXPECT_EQ(ecz.interpolation, model::Interpolation::Cubic);
  EXPECT_DOUBLE_EQ(spec.locationRad[model::locationIndex(Axis::Y, 2)], 18.5e-6);
  ASSERT_EQ(spec.grids.size(), 1u);
  EXPECT_EQ(spec.grids[0].component, 2);
  EXPECT_EQ(spec.grids[0].axesMm[0], (std::vector<double>{0, 10}));
  // Row-major in the order of "over": values[i][j] -> i * n1 + j.
  ASSERT_EQ(spec.grids[0].valuesMm.size(), 4u);
  EXPECT_DOUBLE_EQ(spec.grids[0].valuesMm[1], 2e-3);
  EXPECT_DOUBLE_EQ(spec.grids[0].valuesMm[2], 3e-3);
  // Not error values: unscaled.
  EXPECT_EQ(spec.topology, "XYFZ");
  ASSERT_TRUE(spec.travelMm[0].has_value());
  EXPECT_EQ((*spec.travelMm[0])[1], 850.0);
  EXPECT_FALSE(spec.travelMm[1].has_value());
  EXPECT_EQ(spec.toolMm, Eigen::Vector3d(0, 0, 120));
  EXPECT_EQ(spec.workpieceMm, Eigen::Vector3d(1, 2, 3));
}

TEST(ModelFileUnits, EveryUnitName) {
  struct Case {
    const char* length;
    const char* angle;
    double mm;   // value of 1 length unit in mm
    double rad;  // value of 1 angle unit in rad
  };
  // 1 arcsec = pi / (180 * 3600) rad = pi / 648000 rad.
  const Case cases[] = {{"mm", "rad", 1.0, 1.0},
                        {"um", "mrad", 1e-3, 1e-3},
                        {"nm", "urad", 1e-6, 1e-6},
                        {"mm", "arcsec", 1.0, std::numbers::pi / 648000.0},
                        {"mm", "deg", 1.0, std::numbers::pi / 180.0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.length) + " " + c.angle);
    const auto spec = machineOf(std::string(R"({"format": "volcomp-model/1", "topology": "FXYZ",
      "error_units": {"length": ")") +
                                c.length + R"(", "angle": ")" + c.angle +
                                R"("}, "components": {"EZZ": 2, "EAZ": 3, "EB0Z": 4}})");
    EXPECT_DOUBLE_EQ(std::get<double>(spec.motion[motionIndex(Axis::Z, MotionKind::EZ)]), 2 * c.mm);
    EXPECT_DOUBLE_EQ(std::get<double>(spec.motion[motionIndex(Axis::Z, MotionKind::EA)]),
                     3 * c.rad);
    EXPECT_DOUBLE_EQ(spec.locationRad[model::locationIndex(Axis::Z, 1)], 4 * c.rad);
    EXPECT_DOUBLE_EQ(lengthUnitToMm(c.length, "f", "p"), c.mm);
    EXPECT_DOUBLE_EQ(angleUnitToRad(c.angle, "f", "p"), c.rad);
  }
  EXPECT_THROW(lengthUnitToMm("inch", "f", "p"), ConfigError);
  EXPECT_THROW(angleUnitToRad("grad", "f", "p"), ConfigError);
}

TEST(ModelFileUnits, EveryUnitHasOneNameAndItsFactor) {
  for (const LengthUnit unit :
       {LengthUnit::Millimetre, LengthUnit::Micrometre, LengthUnit::Nanometre}) {
    SCOPED_TRACE(unitName(unit));
    EXPECT_EQ(lengthUnitFromName(unitName(unit)), unit);
    EXPECT_EQ(lengthUnitFactor(unitName(unit)), toMm(unit));
    EXPECT_EQ((ErrorUnits{unit, AngleUnit::Radian}.lengthToMm()), toMm(unit));
  }
  for (const AngleUnit unit : {AngleUnit::Radian, AngleUnit::Milliradian, AngleUnit::Microradian,
                               AngleUnit::Arcsecond, AngleUnit::Degree}) {
    SCOPED_TRACE(unitName(unit));
    EXPECT_EQ(angleUnitFromName(unitName(unit)), unit);
    EXPECT_EQ(angleUnitFactor(unitName(unit)), toRad(unit));
    EXPECT_EQ((ErrorUnits{LengthUnit::Millimetre, unit}.angleToRad()), toRad(unit));
  }
  EXPECT_EQ(toMm(LengthUnit::Micrometre), 1e-3);
  EXPECT_EQ(toRad(AngleUnit::Degree), std::numbers::pi / 180.0);
  EXPECT_FALSE(lengthUnitFromName("inch"));
  EXPECT_FALSE(angleUnitFromName("grad"));
  EXPECT_FALSE(lengthUnitFromName("MM"));
}

TEST(ModelFileUnits, ChainAnglesAreDegrees) {
  const ModelDocument doc = parseModel(nlohmann::json::parse(R"({
    "format": "volcomp-model/1", "name": "c", "chain": {"convention": "mdh", "links": [
      {"joint": "revolute", "theta": 90, "d": 10, "a": 20, "alpha": -45,
       "dtheta": 0.5, "dd": 0.01, "da": -0.02, "dalpha": 0.001},
      {"joint": "fixed", "rotation_deg": [0, 180, 0], "translation": [1, 2, 3],
       "drotation_deg": [0.1, 0, 0], "dtranslation": [0, 0, 0.004]}]}})"),
                                       "chain.json");
  const auto& chain = std::get<model::DhChainSpec>(doc.spec);
  EXPECT_EQ(chain.name, "c");
  EXPECT_EQ(chain.convention, model::DhConvention::Modified);
  ASSERT_EQ(chain.links.size(), 2u);
  const double deg = std::numbers::pi / 180.0;
  const model::DhLinkSpec& l0 = chain.links[0];
  EXPECT_EQ(l0.joint, model::JointType::Revolute);
  EXPECT_FALSE(l0.isTransform);
  EXPECT_DOUBLE_EQ(l0.thetaRad, 90 * deg);
  EXPECT_DOUBLE_EQ(l0.dMm, 10);
  EXPECT_DOUBLE_EQ(l0.aMm, 20);
  EXPECT_DOUBLE_EQ(l0.alphaRad, -45 * deg);
  EXPECT_DOUBLE_EQ(l0.dThetaRad, 0.5 * deg);
  EXPECT_DOUBLE_EQ(l0.dDMm, 0.01);
  EXPECT_DOUBLE_EQ(l0.dAMm, -0.02);
  EXPECT_DOUBLE_EQ(l0.dAlphaRad, 0.001 * deg);
  const model::DhLinkSpec& l1 = chain.links[1];
  EXPECT_TRUE(l1.isTransform);
  EXPECT_EQ(l1.joint, model::JointType::Fixed);
  EXPECT_DOUBLE_EQ(l1.rotationRad.y(), std::numbers::pi);
  EXPECT_EQ(l1.translationMm, Eigen::Vector3d(1, 2, 3));
  EXPECT_DOUBLE_EQ(l1.dRotationRad.x(), 0.1 * deg);
  EXPECT_DOUBLE_EQ(l1.dTranslationMm.z(), 0.004);
  EXPECT_EQ(doc.units.angle, AngleUnit::Degree);
}

}  // namespace
}  // namespace volcomp::config
