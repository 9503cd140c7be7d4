#pragma once
/// The model's composition written as the model file format defines it: one homogeneous
/// transform per carriage, multiplied along the chain. This is the reference: evaluate(),
/// evaluateBatch(), solveOffset() and solveOffsetBatch() compute the same numbers by faster
/// paths, and the tests hold them to it (1e-11 mm, 1e-14 rad).
///
/// Names: `aMb` is the pose of frame b in frame a, the transform that maps coordinates in b to
/// coordinates in a (so `aMb * bMc = aMc`). Frames: F the machine frame (bed), W the workpiece,
/// T the tool tip; for each axis K the carriage frame, and its nominal frame (where the carriage
/// would be without errors). Lengths mm, angles rad.
///
/// For axis K at commanded position q_K, with d_K = Rz(EC0K) Ry(EB0K) Rx(EA0K) e_K its direction:
///   nominalMcarriage = E_K(q) = Trans(EXK, EYK, EZK) Rz(ECK) Ry(EBK) Rx(EAK)   (error motion)
///   parentMnominal   = Trans(+q_K d_K) tool side, Trans(-q_K d_K) workpiece side (ISO 841)
///   parentMcarriage  = C_K(q) = parentMnominal nominalMcarriage
/// and along the topology (workpiece-side axes W1..Wn from the workpiece to the frame, tool-side
/// axes T1..Tn from the frame to the tool):
///   frameMworkpiece = C_Wn ... C_W1 Trans(w)         (H_FW, w the workpiece offset)
///   frameMtool      = C_T1 ... C_Tn Trans(t)         (H_FT, t the tool offset)
///   workpieceMtool  = frameMworkpiece^-1 frameMtool  (H_WT)
/// The actual tool point p(q) is the translation of workpieceMtool plus the grid terms, the
/// nominal point p0(q) = q + t - w, the volumetric error E(q) = p(q) - p0(q) (workpiece frame),
/// the angular error the rotation vector (log map) of the rotation of workpieceMtool.

#include <cstdint>

#include <Eigen/Geometry>

#include "volcomp/model/machine_model.hpp"

namespace volcomp::model {

/// The chain's poses at one point (mm, rad).
struct ChainPoses {
  Eigen::Isometry3d frameMworkpiece = Eigen::Isometry3d::Identity();  ///< H_FW
  Eigen::Isometry3d frameMtool = Eigen::Isometry3d::Identity();       ///< H_FT
  Eigen::Isometry3d workpieceMtool = Eigen::Isometry3d::Identity();   ///< H_WT
};

/// The pose of carriage `axis` relative to what carries it, C_K(q) = Trans(+-q_K d_K) E_K(q), for
/// the commanded positions qMm and the 18 motion-error values (internal units, motionIndex order).
Eigen::Isometry3d parentMcarriage(const MachineModel& model, Axis axis, const Eigen::Vector3d& qMm,
                                  const MotionValues& values) noexcept;

/// frameMworkpiece, frameMtool and workpieceMtool for the commanded positions qMm, the given
/// motion-error values and tool offset toolMm (tool tip relative to the last tool-side carriage).
ChainPoses composeChain(const MachineModel& model, const Eigen::Vector3d& qMm,
                        const MotionValues& values, const Eigen::Vector3d& toolMm) noexcept;

/// The 18 motion-error values at qMm, each error function evaluated on its own at the position
/// clamped to the axis travel (ErrorFunction::value with the axis' direction). Returns the
/// clamped-axes bitmask (bit K: axis K was outside its travel).
std::uint8_t referenceMotion(const MachineModel& model, const Eigen::Vector3d& qMm,
                             const Directions& directions, MotionValues& values) noexcept;

/// E(q) (mm, workpiece frame) and the angular error (rad) by composeChain with the model's tool
/// offset, grids added: what evaluate(model, ws, qMm, directions, EvalMode::Exact) computes.
/// The position is formed as p(q) - p0(q) from points of up to ~1e3 mm, so E carries their
/// rounding (~1e-13 mm); the fast paths keep E's own relative precision. noexcept, no allocation.
PointError evaluateReference(const MachineModel& model, const Eigen::Vector3d& qMm,
                             const Directions& directions = {}) noexcept;

}  // namespace volcomp::model
