// The AVX2 + FMA build of the dense QR kernels (see dense_qr.hpp), compiled with -mavx2 -mfma.
//
// Eigen's templates compiled here differ from the baseline build's but would have the same
// symbol names, and the linker keeps one copy of each: a baseline caller could then run AVX2
// code. Renaming Eigen's namespace for this file makes every instantiation here a symbol of its
// own. Nothing Eigen-typed crosses the file's boundary (dense_qr.hpp takes raw pointers), so
// this file includes no other header of the project.

#define Eigen volcomp_eigen_avx2
#define VOLCOMP_DENSE_QR_NAMESPACE avx2
#include "dense_qr_impl.inc"
