// Daemon configuration files (volcompd --config): text -> JSON -> DaemonConfig with the transport
// section of every kind (Modbus TCP and RTU register maps, CAN with inline signals or DBC
// references, LinuxCNC HAL pins), as loadDaemonConfig reads them. The file is named as if it were
// in the examples folder, so that a "dbc" reference to the example database resolves as it would
// beside a real configuration. What is accepted must be usable: finite timings and limits, a
// finite ramp-out time, a transport that names itself and its endpoint.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "volcomp/config/daemon_config.hpp"
#include "volcomp/config/json_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  const std::string file = VOLCOMP_EXAMPLES_DIR + "/fuzz-volcompd.json";
  try {
    const nlohmann::json document = config::parseJsonText(fuzz::text(data, size), file);
    const config::DaemonConfig c = config::parseDaemonConfig(document, file);
    fuzz::require(std::isfinite(c.cyclePeriodMs) && c.cyclePeriodMs > 0.0,
                  "cycle period not positive");
    fuzz::require(std::isfinite(c.staleTimeoutMs) && c.staleTimeoutMs > c.cyclePeriodMs,
                  "stale timeout not above the period");
    for (const loop::AxisLimits& a : c.limiter.axes) {
      fuzz::require(a.maxOffsetMm > 0.0 && std::isfinite(a.maxOffsetMm), "max offset not positive");
      fuzz::require(a.maxRateMmS > 0.0 && std::isfinite(a.maxRateMmS), "max rate not positive");
    }
    fuzz::require(std::isfinite(config::rampOutSeconds(c.limiter)), "ramp-out time not finite");
    fuzz::require(!c.modelPath.empty(), "no model path");
    fuzz::require(!config::transportType(c.transport).empty(), "transport without a type");
    fuzz::require(!config::transportEndpoint(c.transport).empty(), "transport without endpoint");
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
