// Calibration measurements (CSV with a header naming the columns): every row read is finite and
// has a positive weight.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "volcomp/calibration/measurements.hpp"
#include "volcomp/config/config_error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  std::istringstream in{std::string(fuzz::text(data, size))};
  try {
    const calibration::MeasurementSet set = calibration::parseMeasurementsCsv(in, "fuzz.csv");
    fuzz::require(!set.points.empty(), "a set without points was accepted");
    for (const calibration::Measurement& m : set.points) {
      fuzz::require(m.qMm.allFinite() && m.errorMm.allFinite() && m.toolMm.allFinite() &&
                        m.angularErrorRad.allFinite(),
                    "a measurement is not finite");
      fuzz::require(m.weight > 0.0 && std::isfinite(m.weight), "a weight is not positive");
      fuzz::require(m.joints.size() == static_cast<std::size_t>(set.jointColumns),
                    "joint count differs from the header");
    }
  } catch (const config::ConfigError& e) {
    fuzz::checkMessage(e);
  }
  return 0;
}
