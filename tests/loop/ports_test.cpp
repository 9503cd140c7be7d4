// Link-error classification: what makes the loop reconnect rather than fault.
#include <gtest/gtest.h>

#include <string>

#include "volcomp/loop/ports.hpp"

namespace volcomp::loop::testing {
namespace {

// A driver's own category that maps its "peer gone" code onto the generic condition.
class DriverCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "driver"; }
  std::string message(int) const override { return "driver error"; }
  std::error_condition default_error_condition(int code) const noexcept override {
    return code == 1 ? std::make_error_condition(std::errc::connection_reset)
                     : std::error_condition(code, *this);
  }
};
const DriverCategory driverCategory;

TEST(IsLinkError, TransportDownCodesAreLinkErrors) {
  for (std::errc e :
       {std::errc::not_connected, std::errc::connection_reset, std::errc::broken_pipe,
        std::errc::network_down, std::errc::host_unreachable, std::errc::connection_aborted,
        std::errc::connection_refused, std::errc::network_unreachable}) {
    EXPECT_TRUE(isLinkError(std::make_error_code(e))) << std::make_error_code(e).message();
    EXPECT_TRUE(isLinkError(std::error_code(static_cast<int>(e), std::system_category())));
  }
}

TEST(IsLinkError, FailedTransactionsOnALiveLinkAreNot) {
  EXPECT_FALSE(isLinkError({}));
  EXPECT_FALSE(isLinkError(std::make_error_code(std::errc::timed_out)));
  EXPECT_FALSE(isLinkError(std::make_error_code(std::errc::bad_message)));
  EXPECT_FALSE(isLinkError(std::error_code(2, driverCategory)));
}

TEST(IsLinkError, DriverCategoriesTakePartThroughTheirConditions) {
  EXPECT_TRUE(isLinkError(std::error_code(1, driverCategory)));
}

}  // namespace
}  // namespace volcomp::loop::testing
