#pragma once
/// Counts heap allocations made by this test executable (any thread), so that a test can assert
/// that a call does not allocate. On glibc (without AddressSanitizer) malloc, calloc and realloc
/// are interposed, which also catches Eigen's own allocations (Eigen calls std::malloc, not
/// operator new); everywhere the replaceable global operator new is counted as well.

#include <cstdint>

namespace volcomp::test {

/// Number of allocations since the program started.
std::uint64_t allocationCount() noexcept;

}  // namespace volcomp::test
