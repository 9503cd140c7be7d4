#pragma once
// Internal: the measured quantities predicted through the (optional) instrument frame, shared by
// the 3-axis and the D-H identification. See identification.hpp for the maths.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "volcomp/calibration/identification.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::calibration::detail {

/// frame = (w_x, w_y, w_z [rad], t_x, t_y, t_z [mm]) or nullptr for the identity.
inline Eigen::Vector3d predictedPositionError(const double* frame, const Eigen::Vector3d& nominalMm,
                                              const Eigen::Vector3d& errorMm) {
  if (frame == nullptr) return errorMm;
  const Eigen::Matrix3d rotation = model::rotationZYX(frame[0], frame[1], frame[2]);
  return rotation * (nominalMm + errorMm) + Eigen::Vector3d(frame[3], frame[4], frame[5]) -
         nominalMm;
}

inline Eigen::Matrix3d exponential(const Eigen::Vector3d& rotationVector) {
  const double angle = rotationVector.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotationVector / angle).toRotationMatrix();
}

inline Eigen::Vector3d predictedAngularError(const double* frame,
                                             const Eigen::Vector3d& angularErrorRad) {
  if (frame == nullptr) return angularErrorRad;
  return model::rotationVector(model::rotationZYX(frame[0], frame[1], frame[2]) *
                               exponential(angularErrorRad));
}

/// Standard parameter descriptions of the six frame parameters.
inline void appendFrameInfo(std::vector<ParameterInfo>& info, const std::string& lengthUnit,
                            double lengthToMm, const std::string& angleUnit, double angleToRad) {
  for (const char* axis : {"rx", "ry", "rz"}) {
    info.push_back({std::string("frame ") + axis, "instrument_frame", angleUnit, 1.0 / angleToRad,
                    true, ParameterInfo::Kind::Angle});
  }
  for (const char* axis : {"tx", "ty", "tz"}) {
    info.push_back({std::string("frame ") + axis, "instrument_frame", lengthUnit, 1.0 / lengthToMm,
                    true, ParameterInfo::Kind::Length});
  }
}

}  // namespace volcomp::calibration::detail
