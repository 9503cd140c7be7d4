// writeModel then parseModel gives the spec back: exactly in mm/rad, to rounding in other units.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "volcomp/config/model_file.hpp"

namespace volcomp::config {
namespace {

using model::Axis;
using model::motionIndex;
using model::MotionKind;

void expectNear(double a, double b, double relative, const std::string& what) {
  EXPECT_LE(std::abs(a - b), relative * std::max(std::abs(a), std::abs(b)))
      << what << ": " << a << " vs " << b;
}

void expectNear(const std::vector<double>& a, const std::vector<double>& b, double relative,
                const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) expectNear(a[i], b[i], relative, what);
}

void expectSameFunction(const model::ErrorFunctionSpec& a, const model::ErrorFunctionSpec& b,
                        double relative, const std::string& what) {
  ASSERT_EQ(a.index(), b.index()) << what;
  if (const double* c = std::get_if<double>(&a)) {
    expectNear(*c, std::get<double>(b), relative, what);
  } else if (const auto* p = std::get_if<model::PolynomialSpec>(&a)) {
    expectNear(p->coefficients, std::get<model::PolynomialSpec>(b).coefficients, relative, what);
  } else {
    const auto& ta = std::get<model::TableSpec>(a);
    const auto& tb = std::get<model::TableSpec>(b);
    EXPECT_EQ(ta.positionsMm, tb.positionsMm) << what;
    EXPECT_EQ(ta.interpolation, tb.interpolation) << what;
    expectNear(ta.values, tb.values, relative, what);
    expectNear(ta.valuesNegative, tb.valuesNegative, relative, what);
  }
}

void expectSameSpec(const model::MachineModelSpec& a, const model::MachineModelSpec& b,
                    double relative) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.topology, b.topology);
  for (int axis = 0; axis < 3; ++axis) EXPECT_EQ(a.travelMm[axis], b.travelMm[axis]);
  EXPECT_EQ(a.toolMm, b.toolMm);
  EXPECT_EQ(a.workpieceMm, b.workpieceMm);
  for (int i = 0; i < 18; ++i) {
    expectSameFunction(a.motion[i], b.motion[i], relative, model::motionName(i));
  }
  for (int i = 0; i < 9; ++i) {
    expectNear(a.locationRad[i], b.locationRad[i], relative, model::locationName(i));
  }
  ASSERT_EQ(a.grids.size(), b.grids.size());
  for (std::size_t g = 0; g < a.grids.size(); ++g) {
    EXPECT_EQ(a.grids[g].component, b.grids[g].component);
    EXPECT_EQ(a.grids[g].over, b.grids[g].over);
    EXPECT_EQ(a.grids[g].axesMm, b.grids[g].axesMm);
    expectNear(a.grids[g].valuesMm, b.grids[g].valuesMm, relative, "grid values");
  }
}

model::MachineModelSpec everyFeature() {
  model::MachineModelSpec spec;
  spec.name = "round trip";
  spec.topology = "YXFZ";
  spec.travelMm[0] = std::array<double, 2>{0, 850};
  spec.travelMm[2] = std::array<double, 2>{-500, 0};
  spec.toolMm = {0.5, -1, 120};
  spec.workpieceMm = {10, 20, 30};
  spec.motion[motionIndex(Axis::X, MotionKind::EX)] =
      model::TableSpec{{0, 100, 200, 300},
                       {0, 0.004, 0.0079, 0.012},
                       {0.001, 0.005, 0.009, 0.013},
                       model::Interpolation::Linear};
  spec.motion[motionIndex(Axis::Y, MotionKind::EY)] = model::TableSpec{
      {0, 50, 100, 150, 200}, {0, 1e-3, 3e-3, 2e-3, 1e-3}, {}, model::Interpolation::Quadratic};
  spec.motion[motionIndex(Axis::Z, MotionKind::EA)] =
      model::TableSpec{{-500, -250, 0}, {1e-6, -2e-6, 3e-6}, {}, model::Interpolation::Cubic};
  spec.motion[motionIndex(Axis::X, MotionKind::EB)] = model::PolynomialSpec{{1e-6, 2e-8, -3e-11}};
  spec.motion[motionIndex(Axis::Y, MotionKind::EC)] = 7.5e-6;
  spec.motion[motionIndex(Axis::Z, MotionKind::EZ)] = -0.0021;
  spec.locationRad[model::locationIndex(Axis::Y, 2)] = 18.5e-6;
  spec.locationRad[model::locationIndex(Axis::Z, 0)] = -1.2e-5;
  model::GridSpec grid2;
  grid2.component = 2;
  grid2.over = {Axis::X, Axis::Y};
  grid2.axesMm = {{0, 400, 850}, {0, 500}};
  grid2.valuesMm = {0, 1e-3, 2e-3, 3e-3, 4e-3, 5e-3};
  model::GridSpec grid3;
  grid3.component = 0;
  grid3.over = {Axis::Z, Axis::X, Axis::Y};
  grid3.axesMm = {{-500, 0}, {0, 850}, {0, 250, 500}};
  for (int i = 0; i < 12; ++i) grid3.valuesMm.push_back(i * 1e-4);
  spec.grids = {grid2, grid3};
  return spec;
}

TEST(ModelFileRoundTrip, MillimetresAndRadiansAreExact) {
  const model::MachineModelSpec spec = everyFeature();
  const nlohmann::json written = writeModel(spec);
  const ModelDocument doc = parseModel(written, "written.json");
  expectSameSpec(spec, std::get<model::MachineModelSpec>(doc.spec), 0.0);
}

TEST(ModelFileRoundTrip, OtherUnitsToRounding) {
  const model::MachineModelSpec spec = everyFeature();
  for (const auto& [length, angle] : std::vector<std::pair<std::string, std::string>>{
           {"um", "urad"}, {"nm", "arcsec"}, {"mm", "deg"}, {"um", "mrad"}}) {
    SCOPED_TRACE(length + " " + angle);
    ErrorUnits units;
    units.length = lengthUnitFromName(length).value();
    units.angle = angleUnitFromName(angle).value();
    const nlohmann::json written = writeModel(spec, units);
    EXPECT_EQ(written["error_units"]["length"], length);
    const ModelDocument doc = parseModel(written, "written.json");
    EXPECT_EQ(unitName(doc.units.length), length);
    EXPECT_EQ(unitName(doc.units.angle), angle);
    // One division and one multiplication by the unit factor: a few ulps.
    expectSameSpec(spec, std::get<model::MachineModelSpec>(doc.spec), 1e-15);
  }
}

TEST(ModelFileRoundTrip, WrittenValuesAreInTheFileUnits) {
  model::MachineModelSpec spec;
  spec.motion[motionIndex(Axis::X, MotionKind::EX)] = 0.004;  // mm
  spec.locationRad[model::locationIndex(Axis::Y, 2)] = 2e-5;  // rad
  ErrorUnits units;
  units.length = LengthUnit::Micrometre;
  units.angle = AngleUnit::Microradian;
  const nlohmann::json written = writeModel(spec, units);
  EXPECT_DOUBLE_EQ(written["components"]["EXX"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(written["components"]["EC0Y"].get<double>(), 20.0);
  EXPECT_FALSE(written["components"].contains("EYX"));  // zero components are left out
}

TEST(ModelFileRoundTrip, Chain) {
  model::DhChainSpec spec;
  spec.name = "arm";
  spec.convention = model::DhConvention::Standard;
  model::DhLinkSpec l0;
  l0.joint = model::JointType::Revolute;
  l0.thetaRad = 0.3;
  l0.dMm = 100;
  l0.aMm = 50;
  l0.alphaRad = std::numbers::pi / 2;
  l0.dAlphaRad = 1e-5;
  l0.dDMm = 0.01;
  model::DhLinkSpec l1;
  l1.joint = model::JointType::Fixed;
  l1.isTransform = true;
  l1.rotationRad = {0.1, 0.2, 0.3};
  l1.translationMm = {1, 2, 3};
  l1.dRotationRad = {0, 1.9e-5, 0};
  model::DhLinkSpec l2;
  l2.joint = model::JointType::Prismatic;
  spec.links = {l0, l1, l2};
  const ModelDocument doc = parseModel(writeModel(spec), "chain.json");
  const auto& back = std::get<model::DhChainSpec>(doc.spec);
  EXPECT_EQ(back.name, spec.name);
  EXPECT_EQ(back.convention, spec.convention);
  ASSERT_EQ(back.links.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const auto& a = spec.links[i];
    const auto& b = back.links[i];
    EXPECT_EQ(a.joint, b.joint);
    EXPECT_EQ(a.isTransform, b.isTransform);
    // Degrees in the file: rad -> deg -> rad costs a few ulps.
    for (auto [x, y] : {std::pair{a.thetaRad, b.thetaRad},
                        {a.dMm, b.dMm},
                        {a.aMm, b.aMm},
                        {a.alphaRad, b.alphaRad},
                        {a.dThetaRad, b.dThetaRad},
                        {a.dDMm, b.dDMm},
                        {a.dAMm, b.dAMm},
                        {a.dAlphaRad, b.dAlphaRad}}) {
      expectNear(x, y, 1e-15, "link " + std::to_string(i));
    }
    for (int k = 0; k < 3; ++k) {
      expectNear(a.rotationRad[k], b.rotationRad[k], 1e-15, "rotation");
      expectNear(a.translationMm[k], b.translationMm[k], 0.0, "translation");
      expectNear(a.dRotationRad[k], b.dRotationRad[k], 1e-15, "drotation");
      expectNear(a.dTranslationMm[k], b.dTranslationMm[k], 0.0, "dtranslation");
    }
  }
}

}  // namespace
}  // namespace volcomp::config
