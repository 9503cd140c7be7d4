#pragma once
// Double vectors through the GCC/Clang vector extension: two lanes (SSE2 on x86-64, NEON on
// AArch64, plain scalar code elsewhere) and four (one AVX register in the AVX2 build, two SSE2
// registers in the baseline one). The model is built without -march flags and GCC's -O2 does not
// vectorise the short fixed loops of the hot path by itself.

#include <cstring>

namespace volcomp::model::detail {

using Double2 = double __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
/// Lane masks of Double4 comparisons (all ones or zero per lane), and 32-bit indices.
using Mask4 = decltype(Double4{} < Double4{});
using Int4 = int __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Double2 load2(const double* p) noexcept {
  Double2 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline void store2(double* p, Double2 v) noexcept {
  std::memcpy(p, &v, sizeof v);
}

[[gnu::always_inline]] inline Double4 load4(const double* p) noexcept {
  Double4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

[[gnu::always_inline]] inline Double2 splat2(double x) noexcept {
  return Double2{x, x};
}

template <class V>
[[gnu::always_inline]] inline V splat(double x) noexcept {
  if constexpr (sizeof(V) == sizeof(double)) {
    return x;
  } else {
    V v;
    for (unsigned i = 0; i < sizeof(V) / sizeof(double); ++i) v[i] = x;
    return v;
  }
}

}  // namespace volcomp::model::detail
