#pragma once
// Internal: the Householder QR of the identification's sensitivity matrix and the application of
// its Q^T, the bulk of a linear identification's time (a 15000 x 147 matrix takes about 0.65
// GFLOP). Eigen is compiled for the baseline x86-64 (SSE2) like the rest of the project; these
// two kernels are compiled a second time for AVX2 and FMA (4 doubles per register, fused
// multiply-add: about 3 times fewer instructions) and chosen at run time by what the CPU has, as
// the model's evaluation kernels are.

#include <Eigen/Core>

namespace volcomp::calibration::detail {

/// QR of the column-major m x n matrix `a` (m >= n) in place, LAPACK's layout: R in the upper
/// triangle, the essential parts of the Householder vectors below the diagonal, their
/// coefficients in tau (n).
void householderQr(double* a, Eigen::Index m, Eigen::Index n, double* tau);

/// x <- Q^T x (x has m entries) for a factorisation made by householderQr.
void applyQTranspose(const double* a, Eigen::Index m, Eigen::Index n, const double* tau, double* x);

/// The two builds, for tests that compare them (the functions above pick one).
bool denseKernelsUseAvx2();
/// For benchmarks and tests: with false, the functions above run the baseline build even on a CPU
/// with AVX2 and FMA (default true: the CPU decides).
void allowAvx2DenseKernels(bool allowed);
namespace baseline {
void householderQr(double* a, Eigen::Index m, Eigen::Index n, double* tau);
void applyQTranspose(const double* a, Eigen::Index m, Eigen::Index n, const double* tau, double* x);
}  // namespace baseline
namespace avx2 {
void householderQr(double* a, Eigen::Index m, Eigen::Index n, double* tau);
void applyQTranspose(const double* a, Eigen::Index m, Eigen::Index n, const double* tau, double* x);
}  // namespace avx2

}  // namespace volcomp::calibration::detail
