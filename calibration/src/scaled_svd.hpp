#pragma once
// Internal: the column-scaled factorisation shared by the linear solve and the analysis.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>

#include "volcomp/calibration/least_squares.hpp"

namespace volcomp::calibration {

/// Js = J D = U S V^T (D = diag(1 / column norms)); for m >= n through Js = Q R, R = U_R S V^T.
struct ScaledSvd {
  /// Takes the Jacobian by value: it is scaled and factorised in place (no copy when moved in).
  /// Without `withU` uSmall stays empty (projectResiduals and step are then not available): the
  /// analysis needs S and V only.
  ScaledSvd(Eigen::MatrixXd jacobian, double rankTolerance, bool withU = true);
  /// U_k^T r.
  Eigen::VectorXd projectResiduals(const Eigen::VectorXd& residuals) const;
  /// Minimum-norm (scaled) Gauss-Newton step dp = -D V_k S_k^-1 U_k^T r from U_k^T r.
  Eigen::VectorXd step(const Eigen::VectorXd& projectedResiduals) const;

  Eigen::VectorXd columnScale;
  Eigen::VectorXd singularValues;
  Eigen::MatrixXd uSmall;
  Eigen::MatrixXd v;
  /// Householder factors of the QR of Js (tall case: Eigen's HouseholderQR in place, LAPACK
  /// layout) and their coefficients.
  Eigen::MatrixXd factors;
  Eigen::VectorXd householderCoefficients;
  bool tall = true;
  int rank = 0;
};

FitStatistics analyseFactorised(const ScaledSvd& svd, const Eigen::VectorXd& residuals,
                                const std::vector<std::string>& names, double rankTolerance,
                                double identifiabilityThreshold);

}  // namespace volcomp::calibration
