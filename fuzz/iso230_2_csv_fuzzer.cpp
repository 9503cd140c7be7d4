// ISO 230-2 positioning runs (CSV with units in the header): read (with and without an axis
// filter), evaluated, and written as JSON, as `volcomp iso230-2 --json` does.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include "fuzz_support.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/metrology/iso230_2.hpp"
#include "volcomp/metrology/iso230_2_json.hpp"
#include "volcomp/metrology/positioning_runs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace volcomp;
  const std::optional<model::Axis> axes[] = {std::nullopt, model::Axis::X};
  for (const std::optional<model::Axis> axis : axes) {
    std::istringstream in{std::string(fuzz::text(data, size))};
    try {
      const metrology::PositioningRuns runs = metrology::parsePositioningCsv(in, "fuzz.csv", axis);
      const metrology::Iso230Result result = metrology::evaluateIso230_2(runs);
      for (const std::string& warning : result.warnings) {
        fuzz::require(config::isPrintable(warning), "a warning is not printable");
      }
      // nlohmann::json::dump throws on invalid UTF-8: everything from the file must be clean.
      metrology::toJson(result).dump(2);
    } catch (const config::ConfigError& e) {
      fuzz::checkMessage(e);
    }
  }
  return 0;
}
