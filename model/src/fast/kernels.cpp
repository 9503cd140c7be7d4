// The fast paths, compiled once per instruction set, one chosen per model at construction. The
// code is target-neutral C++ (plain doubles for one point, the compiler vector types of simd.hpp
// for four), so every build compiles the same source and the results differ by rounding only:
// - the baseline: no target attribute, the compiler's default instructions (SSE2 on x86-64, NEON
//   on AArch64, scalar code where there is no SIMD), what every CPU runs;
// - on x86-64 with GCC or Clang, a second build for AVX2 with FMA (one register per four lanes,
//   fused multiply-adds: a third fewer instructions per point, bench/model/README.md), chosen
//   when the CPU has both (__builtin_cpu_supports).
// VOLCOMP_MODEL_DISPATCH=OFF (VOLCOMP_MODEL_NO_DISPATCH) builds the baseline alone: no target
// attribute, no CPU detection; tests/model/portable/check.sh builds and tests it that way.
//
// Why not Highway's dynamic dispatch (libhwy-dev 1.0.3, tried): its foreach_target.h and
// HWY_DYNAMIC_DISPATCH compiled and passed every model test with GCC, but libhwy.so runs a timer
// calibration (RDTSCP) when it is loaded, which valgrind 3.19 (Debian 12) cannot decode: every
// program linking the model died with SIGILL under callgrind, which is how this project compares
// instruction counts. Without the library (header-only use) Highway brings nothing over the two
// pragmas below. Why not its vectors or xsimd's for the lanes: see simd.hpp.

// GCC and Clang note that the four-lane vectors are passed differently with and without AVX
// (-Wpsabi): they only cross functions that are inlined or local to one build's namespace, so no
// calling convention crosses a boundary.
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wpsabi"
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "fast/eval_plan.hpp"
#include "fast/simd.hpp"
#include "piecewise.hpp"
#include "small_angle.hpp"
#include "volcomp/model/so3.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(VOLCOMP_MODEL_NO_DISPATCH)
#define VOLCOMP_MODEL_X86_DISPATCH 1
#else
#define VOLCOMP_MODEL_X86_DISPATCH 0
#endif

namespace volcomp::model::detail {

namespace baseline {
#include "fast/eval_kernels.inc"
}  // namespace baseline

#if VOLCOMP_MODEL_X86_DISPATCH
#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2,fma"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma")
#endif
namespace avx2 {
#include "fast/eval_kernels.inc"
}  // namespace avx2
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

const Kernels& selectKernels() noexcept {
#if VOLCOMP_MODEL_X86_DISPATCH
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return avx2::kKernels;
#endif
  return baseline::kKernels;
}

const Kernels& genericKernels() noexcept {
  return baseline::kKernels;
}

}  // namespace volcomp::model::detail
