#include "allocation_counter.hpp"

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
std::atomic<std::uint64_t> g_allocations{0};
// Trivially initialised thread_local in the executable: reading it inside malloc cannot
// allocate (static TLS, no lazy initialisation).
thread_local bool t_counting = false;
thread_local std::uint64_t t_allocations = 0;

void countOne() noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (t_counting) ++t_allocations;
}
}  // namespace

namespace volcomp::testutil {

std::uint64_t allocationCount() noexcept {
  return g_allocations.load(std::memory_order_relaxed);
}

AllocationScope::AllocationScope() noexcept {
  t_allocations = 0;
  t_counting = true;
}

AllocationScope::~AllocationScope() {
  t_counting = false;
}

std::uint64_t AllocationScope::count() const noexcept {
  return t_allocations;
}

}  // namespace volcomp::testutil

#if defined(__GLIBC__) && !defined(VOLCOMP_MALLOC_IS_SANITIZED)
// Forward to glibc's own allocator (same heap, so free/realloc stay consistent); the definitions
// in the executable take precedence over libc's for every library loaded with it, and
// libstdc++'s operator new reaches them too.
extern "C" {
void* __libc_malloc(std::size_t size) noexcept;
void* __libc_calloc(std::size_t count, std::size_t size) noexcept;
void* __libc_realloc(void* pointer, std::size_t size) noexcept;

void* malloc(std::size_t size) noexcept {
  countOne();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  countOne();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  countOne();
  return __libc_realloc(pointer, size);
}
}
#else
// Without malloc interposition, count the replaceable operator new; the array and nothrow forms
// are replaced too, so that none of them bypasses the count.
void* operator new(std::size_t size) {
  countOne();
  if (void* pointer = std::malloc(size == 0 ? 1 : size)) return pointer;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  countOne();
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* pointer) noexcept {
  std::free(pointer);
}
void operator delete[](void* pointer) noexcept {
  std::free(pointer);
}
void operator delete(void* pointer, std::size_t) noexcept {
  std::free(pointer);
}
void operator delete[](void* pointer, std::size_t) noexcept {
  std::free(pointer);
}
#endif
