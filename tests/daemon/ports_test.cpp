// Link-error classification (what makes the loop reconnect rather than fault) and the transport
// registry volcompd picks its driver from.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fakes.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/daemon/ports.hpp"
#include "volcomp/daemon/transport_registry.hpp"

namespace volcomp::daemon::testing {
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

config::DaemonConfig configWithTransport(const std::string& type) {
  config::DaemonConfig c;
  c.file = "d.json";
  c.transportType = type;
  c.transport = {{"type", type}, {"host", "10.0.0.2"}};
  return c;
}

TEST(TransportRegistry, BuildsThePortOfTheConfiguredType) {
  TransportRegistry registry;
  std::string seenHost, seenFile;
  registry.add("modbus-tcp", [&](const nlohmann::json& section, const std::string& file) {
    seenHost = section.at("host").get<std::string>();
    seenFile = file;
    return std::make_unique<FakePort>();
  });
  EXPECT_TRUE(registry.has("modbus-tcp"));
  auto port = registry.create(configWithTransport("modbus-tcp"));
  EXPECT_NE(port, nullptr);
  EXPECT_EQ(seenHost, "10.0.0.2");
  EXPECT_EQ(seenFile, "d.json");
}

TEST(TransportRegistry, UnbuiltTransportIsAConfigErrorAtTransportType) {
  TransportRegistry registry;
  registry.add("modbus-tcp", [](const nlohmann::json&, const std::string&) {
    return std::make_unique<FakePort>();
  });
  try {
    registry.create(configWithTransport("can"));
    FAIL();
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(e.file(), "d.json");
    EXPECT_EQ(e.keyPath(), "transport.type");
    EXPECT_NE(e.message().find("modbus-tcp"), std::string::npos) << e.what();
  }
}

TEST(TransportRegistry, DriverParseErrorsPassThrough) {
  TransportRegistry registry;
  registry.add(
      "modbus-rtu",
      [](const nlohmann::json&, const std::string& file) -> std::unique_ptr<ControllerPort> {
        throw config::ConfigError(file, "transport.baud", "expected an integer");
      });
  EXPECT_THROW(registry.create(configWithTransport("modbus-rtu")), config::ConfigError);
}

}  // namespace
}  // namespace volcomp::daemon::testing
