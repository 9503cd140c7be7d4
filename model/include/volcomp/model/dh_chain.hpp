#pragma once
/// Denavit-Hartenberg chains (docs/model-file.md "Denavit-Hartenberg chains").
/// Standard: A_i = Rz(theta_i) Trans(0,0,d_i) Trans(a_i,0,0) Rx(alpha_i);
/// modified (Craig): A_i = Rx(alpha_i) Trans(a_i,0,0) Rz(theta_i) Trans(0,0,d_i);
/// fixed transform: Trans(x,y,z) Rz(rz) Ry(ry) Rx(rx). T = A_1 A_2 ... A_n.
/// A prismatic joint's variable adds to d, a revolute joint's to theta. T_nominal uses the nominal
/// parameters, T_actual every parameter plus its deviation (for a fixed transform: translation +
/// dtranslation and rotation + drotation inside the same Trans Rz Ry Rx product). The error is the
/// last column of T_actual - T_nominal (Bulla Ramos et al. 2018, eq. 13), all in the chain's base
/// frame. Internal units: mm and rad (the config layer converts the file's degrees).

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/model/types.hpp"

namespace volcomp::model {

enum class DhConvention : std::uint8_t { Standard, Modified };
enum class JointType : std::uint8_t { Prismatic, Revolute, Fixed };

struct DhLinkSpec {
  JointType joint = JointType::Fixed;
  /// true for a fixed transform given as rotation + translation instead of D-H parameters.
  bool isTransform = false;
  // D-H parameters (nominal) and deviations (actual = nominal + deviation).
  double thetaRad = 0, dMm = 0, aMm = 0, alphaRad = 0;
  double dThetaRad = 0, dDMm = 0, dAMm = 0, dAlphaRad = 0;
  // Fixed transform (isTransform): rotations about X, Y, Z (rad) and translation (mm), nominal
  // geometry, plus optional deviations (file keys `drotation_deg`, `dtranslation`). Bulla Ramos et al.'s
  // error matrix M is a fixed transform with zero nominal and a deviation rotation about Y.
  Eigen::Vector3d rotationRad = Eigen::Vector3d::Zero();
  Eigen::Vector3d translationMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d dRotationRad = Eigen::Vector3d::Zero();
  Eigen::Vector3d dTranslationMm = Eigen::Vector3d::Zero();
};

struct DhChainSpec {
  std::string name;
  DhConvention convention = DhConvention::Standard;
  std::vector<DhLinkSpec> links;
};

/// Result of evaluating a chain at joint values.
struct DhResult {
  Eigen::Matrix4d tNominal = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d tActual = Eigen::Matrix4d::Identity();
  /// Last column of T_actual - T_nominal (mm).
  Eigen::Vector3d errorMm = Eigen::Vector3d::Zero();
  /// Rotation vector of R_nominal^T R_actual (rad).
  Eigen::Vector3d angularErrorRad = Eigen::Vector3d::Zero();
};

class DhChain {
 public:
  /// Throws ModelError on an empty chain, non-finite parameters, or a fixed transform
  /// (isTransform) whose joint is not Fixed.
  explicit DhChain(DhChainSpec spec);
  const DhChainSpec& spec() const noexcept { return spec_; }
  /// Number of prismatic + revolute joints (the values `evaluate` takes, in chain order).
  int jointCount() const noexcept { return jointCount_; }
  /// jointValues: jointCount() values, mm for prismatic and rad for revolute joints, in chain
  /// order; fixed links take none (may be null when jointCount() is 0). T_nominal uses nominal
  /// parameters only, T_actual adds every deviation. Never allocates.
  DhResult evaluate(const double* jointValues) const noexcept;

 private:
  DhChainSpec spec_;
  int jointCount_ = 0;
};

}  // namespace volcomp::model
