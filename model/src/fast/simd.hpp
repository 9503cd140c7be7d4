#pragma once
// Four doubles side by side (and two, and masks and indices) as the compiler's own vector types
// (GCC and Clang `vector_size`): +, -, *, comparisons and `?:` work lane by lane, and a double
// mixes with a vector as a value in every lane, so the composition is written once as a template
// over its lane type, instantiated for `double` (one point) and for Double4 (evaluateBatch). The
// compiler lowers the types to whatever the target has: one AVX register or two SSE2 registers
// on x86-64, two NEON registers on AArch64, POWER VSX, plain scalar code on a CPU without SIMD.
//
// Why not a SIMD library's vector type (Highway libhwy-dev 1.0.3, xsimd libxsimd-dev 8.1, both
// considered; neither tried in code):
// - The lane count must be four on every target, so that one block and its shuffles serve all
//   builds. xsimd's batch<double> has the native width of the architecture it is built for (two
//   lanes on SSE2 and NEON; make_sized_batch_t<double, 4> is void there), and 8.1 has no batch at
//   all on POWER, s390x or RISC-V; Highway's width follows its target too (one lane on GCC 12.2's
//   x86-64 baseline, where EMU128 is disabled for a GCC bug).
// - The composition keeps its lanes in structs and arrays (18 component vectors, three 3x3
//   matrices): Highway's SVE and RVV vectors are sizeless and cannot be members or elements.
// - Highway's operations take a descriptor and Set() for every constant, so the one-point path
//   (plain double) and the batch could no longer share one template.
// The instructions generated are the same as a library's (vaddpd, vfmadd, vshufpd, ...).

namespace volcomp::model::detail {

using Double2 = double __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
/// Lane masks of Double4 comparisons (all ones or zero per lane), and 32-bit indices.
using Mask4 = decltype(Double4{} < Double4{});
using Int4 = int __attribute__((vector_size(16)));

// The loads, stores and broadcasts are in eval_kernels.inc, compiled inside each build's namespace:
// Clang refuses a function returning a four-double vector that is shared between code with and
// without AVX (the two calling conventions differ), even when it is inlined.

}  // namespace volcomp::model::detail
