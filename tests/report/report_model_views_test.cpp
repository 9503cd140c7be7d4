// What the report draws of a model is the model: component curves against ErrorFunction::value,
// map cells and volume statistics against evaluate() point by point.

#include <gtest/gtest.h>

#include <cmath>
#include <variant>

#include "volcomp/config/model_file.hpp"
#include "volcomp/report/model_views.hpp"

namespace volcomp::report {
namespace {

using model::Axis;
using model::Direction;

const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

model::MachineModel exampleModel(const std::string& file) {
  return model::MachineModel(
      std::get<model::MachineModelSpec>(config::loadModelFile(kExamples + "/" + file).spec));
}

TEST(ModelViews, WorkingVolumeIsTheTravel) {
  const model::MachineModel vmc = exampleModel("vmc-xyfz-21.json");
  const WorkingVolume v = workingVolume(vmc);
  EXPECT_EQ(v.rangeMm[0], (std::array<double, 2>{0, 850}));
  EXPECT_EQ(v.rangeMm[1], (std::array<double, 2>{0, 500}));
  EXPECT_EQ(v.rangeMm[2], (std::array<double, 2>{-500, 0}));
  EXPECT_TRUE(v.fromTravel[0] && v.fromTravel[1] && v.fromTravel[2]);
}

TEST(ModelViews, WithoutTravelTheTablesSpanTheRange) {
  model::MachineModelSpec spec;
  spec.motion[0] =
      model::TableSpec{{-20, 0, 300}, {0, 1e-3, 2e-3}, {}, model::Interpolation::Linear};
  spec.grids.push_back({2, {Axis::X, Axis::Y}, {{0, 400}, {10, 90}}, {0, 0, 0, 0}});
  const WorkingVolume v = workingVolume(model::MachineModel(spec));
  EXPECT_EQ(v.rangeMm[0], (std::array<double, 2>{-20, 400}));
  EXPECT_EQ(v.rangeMm[1], (std::array<double, 2>{10, 90}));
  EXPECT_EQ(v.rangeMm[2], (std::array<double, 2>{0, 100}));  // nothing on Z: a default
  EXPECT_FALSE(v.fromTravel[0]);
}

TEST(ModelViews, ComponentCurvesAreTheErrorFunctionsInMicrometresAndMicroradians) {
  const model::MachineModel vmc = exampleModel("vmc-xyfz-21.json");
  const std::vector<ComponentView> views = componentViews(vmc, workingVolume(vmc), 101);
  ASSERT_EQ(views.size(), 18U);  // all 18 motion errors are given
  for (const ComponentView& view : views) {
    const model::ErrorFunction& f = vmc.motion(view.index);
    const double scale = view.angular ? 1e6 : 1e3;
    EXPECT_EQ(view.unit, view.angular ? "µrad" : "µm");
    ASSERT_EQ(view.curves.size(), f.isBidirectional() ? 2U : 1U) << view.name;
    for (const ComponentCurve& curve : view.curves) {
      ASSERT_EQ(curve.positionsMm.size(), 101U);
      for (std::size_t i = 0; i < curve.positionsMm.size(); ++i) {
        EXPECT_DOUBLE_EQ(curve.values[i], f.value(curve.positionsMm[i], curve.direction) * scale)
            << view.name;
      }
    }
  }
  const ComponentView& exx = views[0];
  EXPECT_EQ(exx.name, "EXX");
  EXPECT_EQ(exx.meaning, "positioning of X");
  EXPECT_EQ(exx.curves[0].direction, Direction::Positive);
  EXPECT_EQ(exx.curves[1].direction, Direction::Negative);
  EXPECT_NE(exx.kind.find("bidirectional"), std::string::npos);
  EXPECT_FALSE(exx.nodes[0].empty());
  EXPECT_EQ(views[1].meaning, "straightness of X in Y");
  EXPECT_EQ(views[3].meaning, "roll of X");
  EXPECT_EQ(views[4].meaning, "pitch of X");
  EXPECT_EQ(views[5].meaning, "yaw of X");
  EXPECT_EQ(views[15].meaning, "tilt of Z about X");
  EXPECT_EQ(views[17].meaning, "roll of Z");
  const auto squareness = locationErrors(vmc);
  ASSERT_EQ(squareness.size(), 3U);
  EXPECT_EQ(squareness[0].first, "EC0Y");  // index order: EC0Y, EA0Z, EB0Z
  EXPECT_NEAR(squareness[0].second, 18.5, 1e-9);
  EXPECT_EQ(squareness[2].first, "EB0Z");
  EXPECT_NEAR(squareness[2].second, -12.0, 1e-9);
}

TEST(ModelViews, MapCellsHoldTheModelsErrorAtTheirCentres) {
  const model::MachineModel vmc = exampleModel("vmc-xyfz-21.json");
  const WorkingVolume volume = workingVolume(vmc);
  const std::vector<PlaneSpec> planes = reportPlanes(volume, {}, 24);
  ASSERT_EQ(planes.size(), 5U);
  EXPECT_DOUBLE_EQ(planes[0].levelMm, 0.0);
  EXPECT_DOUBLE_EQ(planes[1].levelMm, -250.0);
  EXPECT_DOUBLE_EQ(planes[2].levelMm, -500.0);
  EXPECT_EQ(planes[3].up, Axis::Z);
  EXPECT_DOUBLE_EQ(planes[3].levelMm, 250.0);  // XZ through the middle of Y
  EXPECT_DOUBLE_EQ(planes[4].levelMm, 425.0);  // YZ through the middle of X
  EXPECT_EQ(planes[0].cellsAcross, 24);
  EXPECT_EQ(planes[0].cellsUp, 14);  // 500 / (850 / 24) = 14.1
  model::Workspace ws;
  for (const PlaneSpec& plane : planes) {
    const ErrorMap map = errorMap(vmc, ws, volume, plane);
    ASSERT_EQ(map.cells.size(), static_cast<std::size_t>(plane.cellsAcross * plane.cellsUp));
    EXPECT_DOUBLE_EQ(map.cells.front().a0, volume.rangeMm[static_cast<int>(plane.across)][0]);
    EXPECT_DOUBLE_EQ(map.cells.back().b1, volume.rangeMm[static_cast<int>(plane.up)][1]);
    double maxMagnitude = 0.0;
    int arrows = 0;
    for (const MapCell& cell : map.cells) {
      Eigen::Vector3d q;
      q[static_cast<int>(plane.across)] = cell.a;
      q[static_cast<int>(plane.up)] = cell.b;
      q[static_cast<int>(normalAxis(plane))] = plane.levelMm;
      const Eigen::Vector3d e = model::evaluate(vmc, ws, q).errorMm * 1e3;
      EXPECT_NEAR((cell.errorUm - e).norm(), 0.0, 1e-9);
      EXPECT_NEAR(cell.magnitude, e.norm(), 1e-9);
      EXPECT_DOUBLE_EQ(cell.outOfPlane, cell.errorUm[static_cast<int>(normalAxis(plane))]);
      maxMagnitude = std::max(maxMagnitude, cell.magnitude);
      arrows += cell.arrow ? 1 : 0;
    }
    EXPECT_DOUBLE_EQ(map.maxMagnitudeUm, maxMagnitude);
    EXPECT_EQ(arrows, (plane.cellsAcross / 2) * (plane.cellsUp / 2));
  }
}

TEST(ModelViews, VolumeStatisticsOverTheGrid) {
  const model::MachineModel vmc = exampleModel("vmc-xyfz-21.json");
  const WorkingVolume volume = workingVolume(vmc);
  model::Workspace ws;
  const VolumeStatistics s = volumeStatistics(vmc, ws, volume, 5);
  EXPECT_EQ(s.points, 125);
  double max = 0.0, sum = 0.0;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        const Eigen::Vector3d q(850.0 * i / 4, 500.0 * j / 4, -500.0 + 500.0 * k / 4);
        const double m = model::evaluate(vmc, ws, q).errorMm.norm() * 1e3;
        max = std::max(max, m);
        sum += m * m;
      }
  EXPECT_NEAR(s.maxUm, max, 1e-9);
  EXPECT_NEAR(s.rmsUm, std::sqrt(sum / 125), 1e-9);
  EXPECT_GT(s.maxAngularUrad, 0.0);
}

}  // namespace
}  // namespace volcomp::report
