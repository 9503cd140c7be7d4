#pragma once
/// Small rotation helpers shared by the model, D-H chains and calibration.

#include <Eigen/Core>

namespace volcomp::model {

/// Rz(c) Ry(b) Rx(a): right-hand rotations about the fixed X, Y, Z axes (docs/model-file.md
/// "Frames, units, signs"), rad. Exact to double precision; uses short series for small angles, so
/// cheap for error angles.
Eigen::Matrix3d rotationZYX(double aRad, double bRad, double cRad) noexcept;

/// Rotation vector (axis * angle, rad) of a rotation matrix: the SO(3) log map. Accurate for small
/// angles (no acos there) and up to pi.
Eigen::Vector3d rotationVector(const Eigen::Matrix3d& rotation) noexcept;

}  // namespace volcomp::model
