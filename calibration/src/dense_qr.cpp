#include "dense_qr.hpp"

#include <atomic>

#define VOLCOMP_DENSE_QR_NAMESPACE baseline
#include "dense_qr_impl.inc"

namespace volcomp::calibration::detail {
namespace {
std::atomic<bool> avx2Allowed{true};
}  // namespace

bool denseKernelsUseAvx2() {
#if VOLCOMP_DENSE_QR_AVX2
  static const bool avx2 = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  }();
  return avx2 && avx2Allowed.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

void allowAvx2DenseKernels(bool allowed) {
  avx2Allowed.store(allowed, std::memory_order_relaxed);
}

void householderQr(double* a, Eigen::Index m, Eigen::Index n, double* tau) {
#if VOLCOMP_DENSE_QR_AVX2
  if (denseKernelsUseAvx2()) return avx2::householderQr(a, m, n, tau);
#endif
  baseline::householderQr(a, m, n, tau);
}

void applyQTranspose(const double* a, Eigen::Index m, Eigen::Index n, const double* tau,
                     double* x) {
#if VOLCOMP_DENSE_QR_AVX2
  if (denseKernelsUseAvx2()) return avx2::applyQTranspose(a, m, n, tau, x);
#endif
  baseline::applyQTranspose(a, m, n, tau, x);
}

}  // namespace volcomp::calibration::detail
