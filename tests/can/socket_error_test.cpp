#include "volcomp/can/channel.hpp"

#include <cerrno>

#include <gtest/gtest.h>

#include "volcomp/can/errors.hpp"
#include "volcomp/daemon/ports.hpp"

namespace volcomp::can {
namespace {

std::error_code sys(int e) {
  return {e, std::system_category()};
}

// The daemon's reconnect logic depends on this mapping, so it is checked without a CAN kernel.
TEST(SocketErrors, InterfaceLossIsALinkError) {
  for (int e : {ENETDOWN, ENODEV, ENXIO}) {
    const std::error_code mapped = mapSocketError(sys(e));
    EXPECT_EQ(mapped, std::errc::network_down) << e;
    EXPECT_TRUE(daemon::isLinkError(mapped)) << e;
  }
}

TEST(SocketErrors, FullTransmitQueueIsADroppedFrameNotALinkError) {
  for (int e : {ENOBUFS, EAGAIN}) {
    const std::error_code mapped = mapSocketError(sys(e));
    EXPECT_EQ(mapped, Errc::TxDropped) << e;
    EXPECT_FALSE(daemon::isLinkError(mapped)) << e;
  }
  EXPECT_EQ(mapSocketError(sys(EINVAL)), sys(EINVAL));
}

TEST(SocketErrors, BusProblemsAreFaultsNotLinkErrors) {
  for (Errc e : {Errc::BusOff, Errc::ErrorPassive, Errc::StaleInput, Errc::NoResponse}) {
    EXPECT_FALSE(daemon::isLinkError(e));
    EXPECT_FALSE(make_error_code(e).message().empty());
    EXPECT_STREQ(make_error_code(e).category().name(), "volcomp.can");
  }
}

}  // namespace
}  // namespace volcomp::can
