// The driver's hot path (read, write) must not allocate once running: the global operator new of
// this test executable counts allocations while a test switches counting on.
// GCC pairs the replaced operator delete (free) with operator new at inlined call sites and warns
// about a mismatch that is not one: our operator new allocates with malloc.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "vcan_layout.hpp"
#include "vcan_util.hpp"
#include "volcomp/can/controller_port.hpp"
#include "volcomp/config/can_config.hpp"

namespace {
std::atomic<bool> counting{false};
std::atomic<std::size_t> allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace volcomp::can {
namespace {

TEST(VcanAllocation, ReadAndWriteDoNotAllocateOnceRunning) {
  test::PeerSocket peer;
  ASSERT_TRUE(peer.ok());
  auto port = std::make_unique<CanControllerPort>(
      config::loadCanLayout(test::testConfig(), "vcan-test.json", "transport"));
  ASSERT_FALSE(port->connect());
  const std::vector<std::uint8_t> frame100{0x87, 0xD6, 0x12, 0xFF, 0xFF, 0xFF, 0x00, 0x00};
  const std::vector<std::uint8_t> frame101{0x60, 0xDA, 0xD9, 0xFF, 0x03, 0x00, 0x00, 0x00};
  auto f100 = frame100;
  auto f101 = frame101;
  loop::AxisSample sample;
  loop::OffsetCommand command;
  std::size_t failures = 0;
  auto cycle = [&](std::uint8_t sequence) {
    f100[7] = sequence;
    f101[7] = sequence;
    peer.send(0x100, f100);
    peer.send(0x101, f101);
    if (port->read(sample)) ++failures;
    command.heartbeat = sequence;
    command.offsetMm = {0.001 * sequence, -0.002, 0.003};
    if (port->write(command)) ++failures;
  };
  for (std::uint8_t s = 0; s < 10; ++s) cycle(s);  // warm-up: Asio caches its handler memory
  // The counter itself works: one visible allocation is seen.
  counting = true;
  int* volatile probe = new int(1);
  counting = false;
  delete probe;
  ASSERT_EQ(allocations.exchange(0), 1u);
  counting = true;
  for (std::uint8_t s = 10; s < 110; ++s) cycle(s);
  counting = false;
  EXPECT_EQ(failures, 0u);
  EXPECT_EQ(allocations.load(), 0u);
  EXPECT_GE(port->stats().completeSets, 100u);
}

}  // namespace
}  // namespace volcomp::can
