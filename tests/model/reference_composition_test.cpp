// The evaluation against a literal transcription of spec section 4 with 4x4 homogeneous
// transforms (Eigen::Isometry3d), including large angles where the small-angle series are not
// used, every topology, and location errors.

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "model_builders.hpp"
#include "volcomp/model/machine_model.hpp"
#include "volcomp/model/so3.hpp"

namespace volcomp::model {
namespace {

Eigen::Isometry3d trans(const Eigen::Vector3d& v) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = v;
  return t;
}

Eigen::Matrix3d zyx(double a, double b, double c) {
  return (Eigen::AngleAxisd(c, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// H_WT per spec section 4: d_K = Rz Ry Rx e_K; E_K = Trans(EX, EY, EZ) Rz(EC) Ry(EB) Rx(EA);
// C_K = Trans(+-q d_K) E_K; H_FW = C_Wn ... C_W1 Trans(w); H_FT = C_T1 ... C_Tn Trans(t).
Eigen::Isometry3d referenceHwt(const MachineModelSpec& spec, const Eigen::Vector3d& q,
                               const MotionValues& v) {
  const Topology topology = Topology::parse(spec.topology);
  auto carriage = [&](Axis axis, double sign) {
    const int k = static_cast<int>(axis);
    const double* l = spec.locationRad.data() + 3 * k;
    const Eigen::Vector3d d = zyx(l[0], l[1], l[2]) * Eigen::Vector3d::Unit(k);
    const double* e = v.data() + 6 * k;
    Eigen::Isometry3d error = trans(Eigen::Vector3d(e[0], e[1], e[2]));
    error.linear() = zyx(e[3], e[4], e[5]);
    return trans(sign * q[k] * d) * error;
  };
  Eigen::Isometry3d hfw = Eigen::Isometry3d::Identity();
  for (const Axis a : topology.workpieceSideFromFrame()) hfw = hfw * carriage(a, -1.0);
  hfw = hfw * trans(spec.workpieceMm);
  Eigen::Isometry3d hft = Eigen::Isometry3d::Identity();
  for (const Axis a : topology.toolSideFromFrame()) hft = hft * carriage(a, 1.0);
  hft = hft * trans(spec.toolMm);
  return hfw.inverse() * hft;
}

TEST(ReferenceComposition, RandomModelsSmallAndLargeAngles) {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(-400, 400);
  for (const double maxAngle : {1e-4, 1e-3, 2e-2, 0.3}) {
    for (int m = 0; m < 60; ++m) {
      MachineModelSpec spec = testing::randomModel(rng, maxAngle, 400, 300);
      spec.grids.clear();
      const MachineModel model(spec);
      Workspace ws;
      for (int i = 0; i < 10; ++i) {
        const Eigen::Vector3d q(u(rng), u(rng), u(rng));
        const PointError e = evaluate(model, ws, q);
        const Eigen::Isometry3d hwt = referenceHwt(spec, q, ws.motion);
        const Eigen::Vector3d p0 = q + spec.toolMm - spec.workpieceMm;
        // The reference forms p - p0 from ~1e3 mm numbers: allow its rounding.
        EXPECT_LT((e.errorMm - (hwt.translation() - p0)).norm(), 1e-11)
            << spec.topology << " max angle " << maxAngle;
        EXPECT_LT((e.angularErrorRad - rotationVector(hwt.linear())).norm(), 1e-14)
            << spec.topology << " max angle " << maxAngle;
      }
    }
  }
}

}  // namespace
}  // namespace volcomp::model
