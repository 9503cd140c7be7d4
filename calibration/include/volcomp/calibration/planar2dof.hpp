#pragma once
/// The planar 2-DOF parallel measuring device of Hanak, Zirn and Ruoff: two sliders on one
/// straight guide (scale readings a, b in mm) carry legs of length La, Lb that meet at the TCP.
/// Calibration against a lattice grid plate (LGP) identifies the device errors of table 1.
///
/// Device frame D: x along the guide, y towards the TCP. Foot joints at
/// A = (a + ea, eha), B = (b + eb, ehb); legs La = La0 + eLa, Lb = Lb0 + eLb (all mm). The TCP is
/// the intersection of the two circles on the +y side (the paper's eq. 2).
///
/// Comparison with the LGP (the paper's section 3): both data sets are taken relative to a
/// reference point (index ref); the LGP reading of the reference point is itself off by (exK, eyK),
/// and the LGP axes are rotated by phi (rad) against the device's:
///   dL_i = R(phi) (r_i - r_ref) - (g_i - g_ref) + (exK, eyK),  R(phi) = [cos sin; -sin cos].
/// Parameters, in this order: eLa, eLb, ea, eha, eb, ehb (mm), phi (rad), exK, eyK (mm).
/// With all nine free the data cannot separate ea from eb nor eha from ehb (a shift of the whole
/// device along x or y changes no difference r_i - r_ref); the paper fixes eb = ehb = 0.

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

enum Planar2DofParameter : int { eLa, eLb, ea, eha, eb, ehb, phi, exK, eyK };
constexpr int kPlanar2DofParameterCount = 9;
using Planar2DofParameters = std::array<double, kPlanar2DofParameterCount>;

/// Name of parameter j ("eLa", ..., "phi", "exK", "eyK").
std::string planar2DofName(int j);

struct Planar2DofGeometry {
  double legAMm = 250.0;  ///< nominal La (manufacturing specification)
  double legBMm = 250.0;  ///< nominal Lb
};

/// TCP in the device frame (mm) for scale readings a, b (mm). Non-intersecting circles give NaN.
Eigen::Vector2d planar2DofForward(const Planar2DofGeometry& geometry, const Planar2DofParameters& u,
                                  double aMm, double bMm) noexcept;

/// Scale readings (a, b) that put the TCP at `tcpMm` (device frame): the inverse kinematics,
/// used to simulate measurements.
Eigen::Vector2d planar2DofInverse(const Planar2DofGeometry& geometry, const Planar2DofParameters& u,
                                  const Eigen::Vector2d& tcpMm) noexcept;

/// One calibration point: the device's scale readings and the LGP reading (LGP frame, mm).
struct Planar2DofSample {
  double aMm = 0.0;
  double bMm = 0.0;
  Eigen::Vector2d lgpMm = Eigen::Vector2d::Zero();
};

/// Least-squares problem over the free parameters; fixed ones keep their values in `values`.
class Planar2DofProblem final : public ResidualProblem {
 public:
  Planar2DofProblem(Planar2DofGeometry geometry, std::vector<Planar2DofSample> samples,
                    int referenceIndex, std::array<bool, kPlanar2DofParameterCount> free,
                    Planar2DofParameters values);

  int parameterCount() const override { return static_cast<int>(freeIndex_.size()); }
  int observationCount() const override { return static_cast<int>(samples_.size()); }
  int residualsPerObservation() const override { return 2; }
  void observationResiduals(const double* p, int i, double* r) const override;
  /// Analytic: the TCP T meets |T - A| = La and |T - B| = Lb, so that
  /// [(T - A)^T; (T - B)^T] dT = [La dLa + (T - A).dA; Lb dLb + (T - B).dB], and
  /// dr/du = R(phi) (dT_i/du - dT_ref/du), dr/dphi = R'(phi) (T_i - T_ref), dr/de_K = I.
  void observationJacobian(const double* p, int i, double* jacobianRowMajor) const override;
  /// All rows at once (the reference point's derivatives taken once).
  void jacobian(const Eigen::VectorXd& p, Eigen::MatrixXd& jacobian) const override;
  /// All residuals at once (the reference point and the rotation taken once).
  void residuals(const Eigen::VectorXd& p, Eigen::VectorXd& r) const override;
  std::string parameterName(int j) const override;
  double parameterStep(int j, double pj) const override;

  /// Start vector (free parameters only) taken from a full parameter set.
  Eigen::VectorXd freeVector(const Planar2DofParameters& u) const;
  /// Full parameter set: `values` with the free ones replaced by p.
  Planar2DofParameters full(const double* p) const;
  /// Index (Planar2DofParameter) of free parameter j.
  int fullIndex(int j) const { return freeIndex_[static_cast<std::size_t>(j)]; }

  /// dT/du (2 x 9, all parameters): the TCP's derivatives in the device frame.
  using TcpDerivative = Eigen::Matrix<double, 2, kPlanar2DofParameterCount>;

 private:
  /// Observation i's two Jacobian rows (free columns) written at out[j * columnStride +
  /// t * rowStride], given the reference point's TCP and derivatives.
  void observationJacobianRows(const Planar2DofParameters& u, int i,
                               const Eigen::Vector2d& tcpReference, const TcpDerivative& dReference,
                               const Eigen::Matrix2d& rotation, double* out, int columnStride,
                               int rowStride) const;
  /// Observation i's two residuals given the reference point's TCP and R(phi).
  Eigen::Vector2d residualsAt(const Planar2DofParameters& u, int i,
                              const Eigen::Vector2d& tcpReference,
                              const Eigen::Matrix2d& rotation) const;

  Planar2DofGeometry geometry_;
  std::vector<Planar2DofSample> samples_;
  int reference_;
  std::vector<int> freeIndex_;
  Planar2DofParameters values_;
};

/// The paper's choice: all parameters free except eb and ehb.
constexpr std::array<bool, kPlanar2DofParameterCount> kPaperFreeParameters{
    true, true, true, true, false, false, true, true, true};

}  // namespace volcomp::calibration
