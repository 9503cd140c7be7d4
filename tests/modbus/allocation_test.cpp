// The driver's hot path (read + write per cycle, including failed transactions) never allocates.
// malloc/calloc/realloc are interposed and counted on the calling thread only, so the simulator's
// server thread (which records every write) does not disturb the count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include <gtest/gtest.h>

#include "loopback_fixture.hpp"
#include "volcomp/modbus/error.hpp"

namespace {
thread_local bool tCounting = false;
thread_local std::uint64_t tAllocations = 0;
}  // namespace

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
extern "C" {
void* __libc_malloc(std::size_t size) noexcept;
void* __libc_calloc(std::size_t count, std::size_t size) noexcept;
void* __libc_realloc(void* pointer, std::size_t size) noexcept;
void* malloc(std::size_t size) noexcept {
  if (tCounting) ++tAllocations;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  if (tCounting) ++tAllocations;
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  if (tCounting) ++tAllocations;
  return __libc_realloc(pointer, size);
}
}
#define VOLCOMP_COUNTING 1
#endif

namespace volcomp::test {
namespace {

class CountAllocations {
 public:
  CountAllocations() {
    tAllocations = 0;
    tCounting = true;
  }
  ~CountAllocations() { tCounting = false; }
  std::uint64_t count() const { return tAllocations; }
};

void cycles(modbus::ModbusControllerPort& port, int n) {
  daemon::AxisSample s;
  daemon::OffsetCommand c;
  for (int i = 0; i < n; ++i) {
    ASSERT_FALSE(port.read(s));
    c.offsetMm = {1e-4 * (i % 7), -1e-4 * (i % 5), 0.0};
    c.heartbeat = static_cast<std::uint16_t>(i);
    ASSERT_FALSE(port.write(c));
  }
}

TEST(ModbusAllocations, ReadAndWriteDoNotAllocate) {
#ifndef VOLCOMP_COUNTING
  GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
#endif
  {
    // The counter sees an allocation (called through a volatile pointer so it is not elided).
    void* (*volatile allocate)(std::size_t) = std::malloc;
    CountAllocations counting;
    std::free(allocate(16));
    ASSERT_EQ(counting.count(), 1U);
  }
  for (bool fc23 : {false, true}) {
    auto lb = Loopback::tcp({100, 200, -50}, {}, fc23);
    ASSERT_FALSE(lb->port->connect());
    cycles(*lb->port, 3);  // warm-up: first use of the error categories, lazy libc state
    std::uint64_t n = 0;
    {
      CountAllocations counting;
      cycles(*lb->port, 200);
      n = counting.count();
    }
    EXPECT_EQ(n, 0U) << (fc23 ? "FC23" : "FC03 + FC16");
  }
}

TEST(ModbusAllocations, FailedTransactionsDoNotAllocate) {
#ifndef VOLCOMP_COUNTING
  GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
#endif
  auto lb = Loopback::tcp({100, 200, -50});
  ASSERT_FALSE(lb->port->connect());
  daemon::AxisSample s;
  lb->machine.exception(lb->now(), 4, 0.0);
  ASSERT_EQ(lb->port->read(s), modbus::Errc::server_device_failure);  // warm-up
  std::uint64_t n = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < 50; ++i) {
      if (lb->port->read(s) != modbus::Errc::server_device_failure) ADD_FAILURE();
      if (lb->port->write(daemon::OffsetCommand{}) != modbus::Errc::server_device_failure) {
        ADD_FAILURE();
      }
    }
    n = counting.count();
  }
  EXPECT_EQ(n, 0U);
}

}  // namespace
}  // namespace volcomp::test
