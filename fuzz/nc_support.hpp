#pragma once
// The NC fuzz targets (ngc, canon): a program runs through the compensation as `volcomp nc` runs
// it, with the example VMC model, a known start position and the default tolerance. A rejected
// program throws NcError with a message fit to print; an accepted one gives a report whose
// figures are finite.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <variant>

#include "fuzz_support.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/model/machine_model.hpp"
#include "volcomp/nc/compensator.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/nc/offset_field.hpp"
#include "volcomp/nc/program_lines.hpp"
#include "volcomp/nc/text_io.hpp"

namespace volcomp::fuzz {

inline nc::OffsetField& exampleField() {
  static nc::OffsetField field(
      std::make_shared<const model::MachineModel>(std::get<model::MachineModelSpec>(
          config::loadModelFile(VOLCOMP_EXAMPLES_DIR + "/vmc-xyfz-21.json").spec)),
      model::EvalMode::Exact);
  return field;
}

/// Start position of the compensation (inside the example model's travel).
inline nc::Vec3 exampleStartMm() {
  return nc::Vec3(10.0, 20.0, -30.0);
}

inline nc::Decimals exampleDecimals() {
  return nc::decimalsForTolerance(nc::CompensateOptions{}.toleranceMm);
}

inline void compensate(nc::ProgramReader& reader, const std::uint8_t* data, std::size_t size) {
  nc::StringSource source{std::string(text(data, size))};
  nc::StringSink sink;
  // A tenth of the default bound on check points per move: one input then takes well under the
  // fuzzer's timeout under the sanitizers on a busy machine, and the refusal is reached sooner.
  nc::CompensateOptions options;
  options.maxCheckPointsPerMove = 100000;
  nc::Compensator compensator(exampleField(), options, exampleStartMm());
  try {
    const nc::NcReport report = compensator.run(reader, source, sink);
    require(std::isfinite(report.peakOffsetMm) && std::isfinite(report.sumSqOffsetMm),
            "report offsets not finite");
    require(report.linesIn >= 0 && report.linesOut >= 0, "negative line counts");
  } catch (const nc::NcError& e) {
    checkMessage(e);
  }
}

}  // namespace volcomp::fuzz
