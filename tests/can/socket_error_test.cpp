#include "volcomp/can/channel.hpp"

#include <cerrno>

#include <gtest/gtest.h>
#include <asio/error.hpp>

#include "volcomp/can/errors.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::can {
namespace {

std::error_code sys(int e) {
  return {e, std::system_category()};
}
std::error_code asioSys(int e) {
  return {e, asio::error::get_system_category()};
}

// The daemon's reconnect logic depends on this mapping, so it is checked without a CAN kernel.
TEST(SocketErrors, InterfaceLossIsALinkError) {
  for (int e : {ENETDOWN, ENODEV, ENXIO}) {
    const std::error_code mapped = mapSocketError(sys(e));
    EXPECT_EQ(mapped, std::errc::network_down) << e;
    EXPECT_TRUE(loop::isLinkError(mapped)) << e;
    // What Asio's socket operations actually report.
    EXPECT_EQ(mapSocketError(asioSys(e)), std::errc::network_down) << e;
  }
}

TEST(SocketErrors, FullTransmitQueueIsADroppedFrameNotALinkError) {
  for (int e : {ENOBUFS, EAGAIN}) {
    const std::error_code mapped = mapSocketError(sys(e));
    EXPECT_EQ(mapped, Errc::TxDropped) << e;
    EXPECT_FALSE(loop::isLinkError(mapped)) << e;
    EXPECT_EQ(mapSocketError(asioSys(e)), Errc::TxDropped) << e;
  }
  EXPECT_EQ(mapSocketError(asio::error::would_block), Errc::TxDropped);
  EXPECT_EQ(mapSocketError(sys(EINVAL)), sys(EINVAL));
}

TEST(SocketErrors, BusProblemsAreFaultsNotLinkErrors) {
  for (Errc e : {Errc::BusOff, Errc::ErrorPassive, Errc::StaleInput, Errc::NoResponse}) {
    EXPECT_FALSE(loop::isLinkError(e));
    EXPECT_FALSE(make_error_code(e).message().empty());
    EXPECT_STREQ(make_error_code(e).category().name(), "volcomp.can");
  }
}

}  // namespace
}  // namespace volcomp::can
