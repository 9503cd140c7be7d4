// volcomp-sim as a process: the LISTENING line, the driver talking to it, fault injection on
// stdin and by --event, the report line at SIGTERM and the --record file.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "subprocess.hpp"
#include "test_maps.hpp"
#include "volcomp/config/modbus_config.hpp"
#include "volcomp/loop/ports.hpp"
#include "volcomp/modbus/controller_port.hpp"
#include "volcomp/modbus/error.hpp"
#include "wait_until.hpp"

namespace volcomp::test {
namespace {

using namespace std::chrono_literals;

const std::string kSim = VOLCOMP_SIM_PATH;
const std::string kExamples = VOLCOMP_EXAMPLES_DIR;

std::filesystem::path tempDir() {
  const auto dir =
      std::filesystem::temp_directory_path() / ("volcomp-sim-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

std::uint16_t listeningPort(testutil::Subprocess& sim) {
  const auto line = sim.readLine(10s);
  if (!line) return 0;
  std::istringstream in(*line);
  std::string word, kind, host;
  unsigned port = 0;
  in >> word >> kind >> host >> port;
  EXPECT_EQ(word, "LISTENING");
  EXPECT_EQ(kind, "tcp");
  EXPECT_EQ(host, "127.0.0.1");
  return static_cast<std::uint16_t>(port);
}

TEST(SimProcess, ServesTheExampleMachineAndReportsAtSigterm) {
  const auto record = tempDir() / "writes.csv";
  testutil::Subprocess sim({kSim, "--config", kExamples + "/sim-vmc.json", "--port", "0",
                            "--record", record.string(), "--event", "0:enable:off"});
  const std::uint16_t port = listeningPort(sim);
  ASSERT_NE(port, 0);

  modbus::ModbusControllerPort driver(
      config::parseModbusSettings(tcpTransportJson(port), "test", "transport"));
  ASSERT_FALSE(driver.connect());
  loop::AxisSample s;
  // The scheduled event at 0 s switches enable off; stdin switches it on again.
  ASSERT_TRUE(testutil::waitUntil([&] { return !driver.read(s) && !s.enable; }));
  sim.writeLine("enable on");
  ASSERT_TRUE(testutil::waitUntil([&] { return !driver.read(s) && s.enable; }));
  // The example raster runs inside X 50..800, Y 50..450 at Z = -200.
  EXPECT_GE(s.positionMm[0], 50.0 - 1e-9);
  EXPECT_LE(s.positionMm[0], 800.0 + 1e-9);
  EXPECT_NEAR(s.positionMm[2], -200.0, 1e-9);
  EXPECT_TRUE(s.homed);

  // Offsets well inside the example's limits (0.1 mm, 0.5 mm/s): 1 um steps.
  loop::OffsetCommand c;
  int writes = 0;
  for (int i = 1; i <= 5; ++i) {
    c.offsetMm = {0.001 * i, -0.0005 * i, 0.0};
    c.heartbeat = static_cast<std::uint16_t>(i);
    ASSERT_FALSE(driver.write(c));
    ++writes;
  }

  sim.writeLine("exception 2");
  std::error_code ec;
  ASSERT_TRUE(testutil::waitUntil([&] {
    return (ec = driver.read(s)) == modbus::Errc::illegal_data_address;
  })) << ec.message();
  sim.writeLine("resume");
  ASSERT_TRUE(testutil::waitUntil([&] { return !driver.read(s); }));

  sim.writeLine("drop-link");
  ASSERT_TRUE(testutil::waitUntil([&] { return loop::isLinkError(driver.read(s)); }));
  sim.writeLine("resume");
  ASSERT_TRUE(testutil::waitUntil([&] { return !driver.connect(); }));
  ASSERT_FALSE(driver.read(s));
  EXPECT_NEAR(s.appliedOffsetMm[0], 0.005, 1e-9) << "the controller kept the applied offsets";
  ASSERT_FALSE(driver.write(c));
  ++writes;

  sim.signal(SIGTERM);
  const auto reportLine = sim.readLine(10s);
  ASSERT_TRUE(reportLine.has_value());
  EXPECT_EQ(sim.waitExit(10s), 0);
  const nlohmann::json report = nlohmann::json::parse(*reportLine);
  EXPECT_EQ(report["writes"], writes);
  EXPECT_EQ(report["limiter_violations"], 0) << report["first_violation"];
  EXPECT_EQ(report["partial_writes"], 0);
  EXPECT_EQ(report["sessions"], 2);
  for (const char* key : {"rms_uncompensated_um", "rms_compensated_um", "max_compensated_um",
                          "max_uncompensated_um", "samples", "duration_s"}) {
    EXPECT_TRUE(report.contains(key)) << key;
  }
  for (const char* axis : {"X", "Y", "Z"}) {
    EXPECT_TRUE(report["axes"][axis].contains("rms_compensated_um")) << axis;
  }
  EXPECT_GT(report["rms_uncompensated_um"].get<double>(), 0.0) << "the true model has errors";

  std::ifstream csv(record);
  std::string line;
  int rows = -1;  // header
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, writes);
}

TEST(SimProcess, BadArgumentsAndConfigurationsExitWithStatus2) {
  {
    testutil::Subprocess sim({kSim, "--config", "/nonexistent/sim.json"});
    EXPECT_EQ(sim.waitExit(10s), 2);
  }
  {
    testutil::Subprocess sim(
        {kSim, "--config", kExamples + "/sim-vmc.json", "--event", "1:explode"});
    EXPECT_EQ(sim.waitExit(10s), 2);
  }
  {
    // A path outside the true model's travel (X 0..850) is refused.
    const auto file = tempDir() / "outside.json";
    nlohmann::json cfg = nlohmann::json::parse(std::ifstream(kExamples + "/sim-vmc.json"));
    cfg["model"] = kExamples + "/vmc-xyfz-21-true.json";
    cfg["path"] = {
        {"type", "circle"}, {"center", {840, 250, -100}}, {"radius_mm", 50}, {"feed_mm_min", 1000}};
    std::ofstream(file) << cfg.dump();
    testutil::Subprocess sim({kSim, "--config", file.string()});
    EXPECT_EQ(sim.waitExit(10s), 2);
  }
}

}  // namespace
}  // namespace volcomp::test
