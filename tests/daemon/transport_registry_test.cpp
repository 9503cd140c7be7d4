// The transport registry volcompd picks its driver from.
#include "volcomp/daemon/transport_registry.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "fakes.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::daemon {
namespace {

using loop::ControllerPort;
using loop::testing::FakePort;

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
}  // namespace volcomp::daemon
