// The driver's hot path (read + write per cycle, including failed transactions) never allocates.
// The shared allocation counter interposes malloc/calloc/realloc; it counts the calling thread
// only, so the simulator's server thread (which records every write) does not disturb the count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include <gtest/gtest.h>

#include "allocation_counter.hpp"
#include "loopback_fixture.hpp"
#include "volcomp/modbus/error.hpp"

namespace volcomp::test {
namespace {

using CountAllocations = volcomp::testutil::AllocationScope;

void cycles(modbus::ModbusControllerPort& port, int n) {
  loop::AxisSample s;
  loop::OffsetCommand c;
  for (int i = 0; i < n; ++i) {
    ASSERT_FALSE(port.read(s));
    c.offsetMm = {1e-4 * (i % 7), -1e-4 * (i % 5), 0.0};
    c.heartbeat = static_cast<std::uint16_t>(i);
    ASSERT_FALSE(port.write(c));
  }
}

TEST(ModbusAllocations, ReadAndWriteDoNotAllocate) {
  if (!volcomp::testutil::kCountsMalloc) {
    GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
  }
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
  if (!volcomp::testutil::kCountsMalloc) {
    GTEST_SKIP() << "malloc interposition needs glibc without sanitizers";
  }
  auto lb = Loopback::tcp({100, 200, -50});
  ASSERT_FALSE(lb->port->connect());
  loop::AxisSample s;
  lb->machine.exception(lb->now(), 4, 0.0);
  ASSERT_EQ(lb->port->read(s), modbus::Errc::server_device_failure);  // warm-up
  std::uint64_t n = 0;
  {
    CountAllocations counting;
    for (int i = 0; i < 50; ++i) {
      if (lb->port->read(s) != modbus::Errc::server_device_failure) ADD_FAILURE();
      if (lb->port->write(loop::OffsetCommand{}) != modbus::Errc::server_device_failure) {
        ADD_FAILURE();
      }
    }
    n = counting.count();
  }
  EXPECT_EQ(n, 0U);
}

}  // namespace
}  // namespace volcomp::test
