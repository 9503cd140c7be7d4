// The model table from an ISO 230-2 evaluation: a model holding only that component gives back the
// measured mean deviations as E along the axis, on tool-side and workpiece-side axes alike, in
// every topology; and the signs of tables sampled for controllers.

#include <gtest/gtest.h>

#include "volcomp/metrology/axis_tables.hpp"
#include "volcomp/metrology/iso230_2_model.hpp"
#include "volcomp/model/topology.hpp"

namespace volcomp::metrology {
namespace {

Iso230Result syntheticResult() {
  Iso230Result r;
  const double targets[] = {-40, 15, 77, 130, 222, 301};
  for (int i = 0; i < 6; ++i) {
    TargetFigures t;
    t.positionMm = targets[i];
    t.meanPositiveMm = 1e-3 * (2.0 + 0.5 * i - 0.1 * i * i);
    t.meanNegativeMm = t.meanPositiveMm + 3e-3;
    r.targets.push_back(t);
  }
  return r;
}

TEST(ModelTable, GivesBackTheMeasuredDeviationsInEveryTopology) {
  const Iso230Result r = syntheticResult();
  for (const std::string& text : model::allTopologies()) {
    const model::Topology topology = model::Topology::parse(text);
    for (int a = 0; a < 3; ++a) {
      const auto axis = static_cast<model::Axis>(a);
      SCOPED_TRACE(text + " axis " + axisName(axis));
      model::MachineModelSpec spec;
      spec.topology = text;
      spec.toolMm = Eigen::Vector3d(0, 0, 120);
      const int index = model::motionIndex(axis, static_cast<model::MotionKind>(a));
      spec.motion[static_cast<std::size_t>(index)] = positioningComponent(r, topology, axis);
      const auto& table = std::get<model::TableSpec>(spec.motion[static_cast<std::size_t>(index)]);
      EXPECT_EQ(table.values.front() > 0, !topology.isWorkpieceSide(axis));
      const model::MachineModel machine(spec);
      model::Workspace ws;
      for (const TargetFigures& t : r.targets) {
        Eigen::Vector3d q(13, -7, 21);
        q[a] = t.positionMm;
        model::Directions up{}, down{};
        up[static_cast<std::size_t>(a)] = model::Direction::Positive;
        down[static_cast<std::size_t>(a)] = model::Direction::Negative;
        EXPECT_NEAR(model::evaluate(machine, ws, q, up).errorMm[a], t.meanPositiveMm, 1e-15);
        EXPECT_NEAR(model::evaluate(machine, ws, q, down).errorMm[a], t.meanNegativeMm, 1e-15);
      }
    }
  }
}

TEST(AxisTables, PositioningErrorSignFollowsTheSide) {
  // EXX = 5 um constant-slope table; tool-side X (FXYZ): e = +EXX; workpiece-side (XYFZ): -EXX.
  for (const char* topology : {"FXYZ", "XYFZ"}) {
    model::MachineModelSpec spec;
    spec.topology = topology;
    spec.travelMm[0] = std::array<double, 2>{0, 100};
    model::TableSpec exx;
    exx.positionsMm = {0, 100};
    exx.values = {0, 0.005};
    spec.motion[0] = exx;
    const AxisGrid grid = makeGrid(axisRange(spec, model::Axis::X), 25);
    ASSERT_EQ(grid.count, 5u);
    const AxisTable table =
        sampleTable(spec, {0}, {}, model::Axis::X, model::Axis::X, grid, model::Direction::Unknown);
    const double sign = std::string(topology) == "FXYZ" ? 1.0 : -1.0;
    for (std::size_t i = 0; i < grid.count; ++i) {
      EXPECT_NEAR(table.errorMm[i], sign * 0.005 * grid.positionMm(i) / 100, 1e-15) << topology;
    }
    EXPECT_EQ(table.components, (std::vector<std::string>{"EXX"}));
    EXPECT_NEAR(table.errorAt(-10), table.errorMm.front(), 0);
    EXPECT_NEAR(table.errorAt(130), table.errorMm.back(), 0);
    EXPECT_NEAR(table.errorAt(37.5), sign * 0.005 * 0.375, 1e-15);
  }
}

TEST(AxisTables, SquarenessIsAnErrorAlongTheOtherAxis) {
  // EC0Y = 100 urad tilts Y's line of motion towards -X: d_Y = (-sin c, cos c, 0), so moving Y by
  // y puts the tool at x = -y sin c (tool side, FXYZ) and, because a workpiece-side carriage moves
  // by -y d_Y while the tool stays, also at -y sin c relative to the workpiece (XYFZ).
  for (const char* topology : {"FXYZ", "XYFZ"}) {
    model::MachineModelSpec spec;
    spec.topology = topology;
    spec.travelMm[1] = std::array<double, 2>{0, 500};
    spec.locationRad[static_cast<std::size_t>(model::locationIndex(model::Axis::Y, 2))] = 100e-6;
    const AxisGrid grid = makeGrid(axisRange(spec, model::Axis::Y), 0);
    EXPECT_DOUBLE_EQ(grid.stepMm, 5.0);
    EXPECT_EQ(grid.count, 101u);
    const AxisTable table =
        sampleTable(spec, {}, {model::locationIndex(model::Axis::Y, 2)}, model::Axis::Y,
                    model::Axis::X, grid, model::Direction::Unknown);
    EXPECT_NEAR(table.errorMm.back(), -500 * std::sin(100e-6), 1e-12) << topology;
    EXPECT_EQ(table.components, (std::vector<std::string>{"EC0Y"}));
  }
}

TEST(AxisTables, AutomaticStepIsRoundAndCoversTheRange) {
  EXPECT_DOUBLE_EQ(makeGrid({0, 850, true}, 0).stepMm, 10.0);
  EXPECT_EQ(makeGrid({0, 850, true}, 0).count, 86u);
  EXPECT_DOUBLE_EQ(makeGrid({0, 2000, true}, 0).stepMm, 20.0);
  EXPECT_DOUBLE_EQ(makeGrid({-300, 0, true}, 0).stepMm, 5.0);
  EXPECT_DOUBLE_EQ(makeGrid({0, 230, true}, 0).stepMm, 2.5);
  const AxisGrid odd = makeGrid({0, 103, true}, 10);
  EXPECT_EQ(odd.count, 12u);
  EXPECT_DOUBLE_EQ(odd.endMm(), 110.0);
  EXPECT_EQ(makeGrid({5, 5, false}, 0).count, 1u);
}

}  // namespace
}  // namespace volcomp::metrology
