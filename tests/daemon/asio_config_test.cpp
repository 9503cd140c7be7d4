// Asio before any standard header, on purpose: Asio chooses how it allocates and frees
// handler memory (aligned_alloc/free or operator new/delete) from a libstdc++ macro that only
// exists once a standard header has been included. Files that included Asio first chose
// differently from the others, and since both choices are inline functions of the same name, a
// GCC ASan volcompd freed with free() what operator new had allocated and aborted at exit. The
// build states the choice (ASIO_HAS_STD_ALIGNED_ALLOC on volcomp_asio); this file, compiled like
// any other, proves the statement reaches a file that includes Asio first.
#include <asio/io_context.hpp>
#include <asio/steady_timer.hpp>

#if !defined(ASIO_HAS_STD_ALIGNED_ALLOC)
#error "Asio's aligned-allocation choice must not depend on include order (see CMakeLists.txt)"
#endif

#include <gtest/gtest.h>

#include <chrono>

namespace {

// The allocation path in question: a timer's wait handler, allocated through thread_info_base
// and freed when the io_context's thread information is destroyed.
TEST(AsioConfig, HandlerMemoryIsAllocatedAndFreedTheSameWay) {
  asio::io_context io;
  asio::steady_timer timer(io, std::chrono::steady_clock::now());
  bool fired = false;
  timer.async_wait([&](const std::error_code&) { fired = true; });
  io.run();
  EXPECT_TRUE(fired);
}

}  // namespace
