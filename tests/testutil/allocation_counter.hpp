#pragma once
/// Counts heap allocations, so that a test can assert that a call does not allocate.
///
/// On glibc (without AddressSanitizer or ThreadSanitizer) malloc, calloc and realloc are
/// interposed: that catches operator new (which allocates with malloc) and also Eigen's own
/// allocations (Eigen calls std::malloc, not operator new). Elsewhere the replaceable global
/// operator new is counted instead.
///
/// The replacements live in allocation_counter.cpp, which must be compiled into exactly one
/// translation unit of the executable: link the CMake target `volcomp_testutil_allocations`
/// (it adds that source), and give the test its own executable, since the replacements apply to
/// the whole program.

#include <cstdint>

// GCC says a sanitizer is on with __SANITIZE_*__, clang (before 17) with __has_feature: the
// sanitizers own malloc, so only operator new is counted then.
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define VOLCOMP_MALLOC_IS_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define VOLCOMP_MALLOC_IS_SANITIZED 1
#endif

namespace volcomp::testutil {

/// Whether malloc/calloc/realloc themselves are counted (glibc without sanitizers); when false
/// only the global operator new is.
#if defined(__GLIBC__) && !defined(VOLCOMP_MALLOC_IS_SANITIZED)
inline constexpr bool kCountsMalloc = true;
#else
inline constexpr bool kCountsMalloc = false;
#endif

/// Number of allocations made by any thread since the program started.
std::uint64_t allocationCount() noexcept;

/// Counts the allocations made by the calling thread while it exists (so that a helper thread,
/// such as a simulator's server, does not disturb the count). Scopes do not nest: the count
/// restarts at zero when one is created and stops when it is destroyed.
class AllocationScope {
 public:
  AllocationScope() noexcept;
  ~AllocationScope();
  AllocationScope(const AllocationScope&) = delete;
  AllocationScope& operator=(const AllocationScope&) = delete;

  /// Allocations by this thread since the scope began.
  std::uint64_t count() const noexcept;
};

}  // namespace volcomp::testutil
