// The reference composition (see composition.hpp): each transform built and multiplied as the
// model file format writes it, with nothing precomputed but the axis directions.

#include "volcomp/model/composition.hpp"

#include <algorithm>

#include "volcomp/model/so3.hpp"

namespace volcomp::model {
namespace {

Eigen::Isometry3d translation(const Eigen::Vector3d& vMm) noexcept {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = vMm;
  return t;
}

// E_K(q) = Trans(EXK, EYK, EZK) Rz(ECK) Ry(EBK) Rx(EAK): the actual carriage in its nominal frame.
Eigen::Isometry3d nominalMcarriage(Axis axis, const MotionValues& values) noexcept {
  const auto value = [&](MotionKind kind) { return values[motionIndex(axis, kind)]; };
  Eigen::Isometry3d e = translation(
      Eigen::Vector3d(value(MotionKind::EX), value(MotionKind::EY), value(MotionKind::EZ)));
  e.linear() = rotationZYX(value(MotionKind::EA), value(MotionKind::EB), value(MotionKind::EC));
  return e;
}

}  // namespace

Eigen::Isometry3d parentMcarriage(const MachineModel& model, Axis axis, const Eigen::Vector3d& qMm,
                                  const MotionValues& values) noexcept {
  // ISO 841: a workpiece-side carriage moves opposite to the commanded direction.
  const double sign = model.topology().isWorkpieceSide(axis) ? -1.0 : 1.0;
  const Eigen::Isometry3d parentMnominal =
      translation(sign * qMm[static_cast<int>(axis)] * model.axisDirection(axis));
  return parentMnominal * nominalMcarriage(axis, values);
}

ChainPoses composeChain(const MachineModel& model, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm) noexcept {
  ChainPoses poses;
  // H_FW = C_Wn ... C_W1 Trans(w): workpieceSideFromFrame() lists Wn (next to the frame) first.
  for (const Axis axis : model.topology().workpieceSideFromFrame()) {
    poses.frameMworkpiece = poses.frameMworkpiece * parentMcarriage(model, axis, qMm, values);
  }
  poses.frameMworkpiece = poses.frameMworkpiece * translation(model.workpieceMm());
  // H_FT = C_T1 ... C_Tn Trans(t): toolSideFromFrame() lists T1 (next to the frame) first.
  for (const Axis axis : model.topology().toolSideFromFrame()) {
    poses.frameMtool = poses.frameMtool * parentMcarriage(model, axis, qMm, values);
  }
  poses.frameMtool = poses.frameMtool * translation(toolMm);
  poses.workpieceMtool = poses.frameMworkpiece.inverse(Eigen::Isometry) * poses.frameMtool;
  return poses;
}

std::uint8_t referenceMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                             const Directions& directions, MotionValues& values) noexcept {
  std::uint8_t clamped = 0;
  for (int k = 0; k < 3; ++k) {
    double q = qMm[k];
    if (const auto& travel = model.spec().travelMm[k]) {
      if (q < (*travel)[0] || q > (*travel)[1])
        clamped = static_cast<std::uint8_t>(clamped | 1u << k);
      q = std::clamp(q, (*travel)[0], (*travel)[1]);
    }
    for (int kind = 0; kind < 6; ++kind) {
      values[6 * k + kind] = model.motion(6 * k + kind).value(q, directions[k]);
    }
  }
  return clamped;
}

PointError evaluateReference(const MachineModel& model, const Eigen::Vector3d& qMm,
                             const Directions& directions) noexcept {
  PointError result;
  MotionValues values{};
  result.clampedAxes = referenceMotion(model, qMm, directions, values);
  const ChainPoses poses = composeChain(model, qMm, values, model.toolMm());
  Eigen::Vector3d pointMm = poses.workpieceMtool.translation();
  for (const Grid& grid : model.grids()) pointMm[grid.component()] += grid.valueMm(qMm.data());
  const Eigen::Vector3d nominalMm = qMm + model.toolMm() - model.workpieceMm();
  result.errorMm = pointMm - nominalMm;
  result.angularErrorRad = rotationVector(poses.workpieceMtool.linear());
  return result;
}

}  // namespace volcomp::model
