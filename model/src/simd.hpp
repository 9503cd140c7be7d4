#pragma once
// Two-lane double vectors through the GCC/Clang vector extension: SSE2 on x86-64, NEON on
// AArch64, plain scalar code elsewhere. The model is built without -march flags and GCC's -O2
// does not vectorise the short fixed loops of the hot path by itself.

#include <cstring>

namespace volcomp::model::detail {

using Double2 = double __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Double2 load2(const double* p) noexcept {
  Double2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store2(double* p, Double2 v) noexcept {
  std::memcpy(p, &v, sizeof v);
}

[[gnu::always_inline]] inline Double2 splat2(double x) noexcept {
  return Double2{x, x};
}

}  // namespace volcomp::model::detail
