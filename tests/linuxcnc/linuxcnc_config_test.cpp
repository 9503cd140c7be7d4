// The LinuxCNC transport section: defaults, values, and each rejection with its key path.
#include "volcomp/config/linuxcnc_config.hpp"

#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/transport_config.hpp"

namespace volcomp::config {
namespace {

using nlohmann::json;

void expectError(const json& section, const std::string& path, const std::string& fragment) {
  try {
    parseTransportSettings(section, "daemon.json", "transport");
    FAIL() << "accepted " << section.dump();
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.file(), "daemon.json");
    EXPECT_EQ(e.keyPath(), path) << e.what();
    EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
  }
}

TEST(LinuxCncConfig, DefaultsAreTheComponentVolcompAtATenthOfAMicrometrePerCount) {
  const TransportSettings t = parseTransportSettings(json{{"type", "linuxcnc"}}, "f", "transport");
  const auto& s = std::get<linuxcnc::HalSettings>(t);
  EXPECT_EQ(s.component, "volcomp");
  EXPECT_EQ(s.countsPerMm, 10000.0);
  EXPECT_EQ(transportType(t), "linuxcnc");
}

TEST(LinuxCncConfig, ReadsComponentAndScale) {
  const auto s = parseLinuxCncSettings(
      json{{"type", "linuxcnc"}, {"component", "comp_2-b"}, {"counts_per_mm", 1000}}, "f", "t");
  EXPECT_EQ(s.component, "comp_2-b");
  EXPECT_EQ(s.countsPerMm, 1000.0);
}

TEST(LinuxCncConfig, Rejections) {
  expectError(json{{"type", "linuxcnc"}, {"host", "x"}}, "transport.host", "unknown key");
  expectError(json{{"type", "linuxcnc"}, {"component", ""}}, "transport.component",
              "HAL component name");
  expectError(json{{"type", "linuxcnc"}, {"component", "a.b"}}, "transport.component",
              "HAL component name");
  expectError(json{{"type", "linuxcnc"}, {"component", std::string(27, 'a')}},
              "transport.component", "1 to 26");
  expectError(json{{"type", "linuxcnc"}, {"counts_per_mm", 0}}, "transport.counts_per_mm",
              "[1.0, 10000000.0]");
  expectError(json{{"type", "linuxcnc"}, {"counts_per_mm", "many"}}, "transport.counts_per_mm",
              "number");
}

TEST(LinuxCncConfig, TheDaemonConfigurationCarriesIt) {
  const json doc = json::parse(R"({
    "position_semantics": "commanded",
    "limiter": {"max_offset_mm": 0.1, "max_rate_mm_s": 0.5},
    "model": "model.json",
    "transport": {"type": "linuxcnc", "component": "vc"}
  })");
  const DaemonConfig c = parseDaemonConfig(doc, "/etc/volcomp/volcompd.json");
  EXPECT_EQ(std::get<linuxcnc::HalSettings>(c.transport).component, "vc");
}

}  // namespace
}  // namespace volcomp::config
