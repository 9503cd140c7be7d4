#include "volcomp/daemon/configuration.hpp"

#include <cmath>
#include <cstdint>
#include <utility>
#include <variant>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/config/model_plausibility.hpp"

namespace volcomp::daemon {
namespace {

std::chrono::nanoseconds fromMs(double ms) noexcept {
  return std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(ms * 1e6)));
}

}  // namespace

LoadedConfiguration loadConfiguration(const std::string& configPath) {
  LoadedConfiguration loaded;
  loaded.config = config::loadDaemonConfig(configPath);
  loaded.model =
      loadCompensationModel(loaded.config.modelPath, config::offsetBoundOf(loaded.config));
  return loaded;
}

std::shared_ptr<loop::CompensationModel> loadCompensationModel(
    const std::string& path, const std::optional<config::OffsetBound>& bound) {
  config::ModelDocument document = config::loadModelFile(path);
  auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw config::ConfigError(path, "chain",
                              "the daemon compensates 3-axis machine models; a D-H chain file "
                              "cannot be used for live compensation");
  }
  std::string name = spec->name.empty() ? path : spec->name;
  model::MachineModel model(std::move(*spec));
  // At start, --check-config and every reload (which runs this on its helper thread): a refused
  // model never reaches the loop, and a refused reload keeps the running one.
  config::requirePlausible(document, config::assessModel(model), bound);
  return std::make_shared<loop::MachineModelCompensation>(std::move(model), std::move(name));
}

loop::LoopSettings loopSettingsFrom(const config::DaemonConfig& c) noexcept {
  loop::LoopSettings s;
  s.period = fromMs(c.cyclePeriodMs);
  s.semantics = c.positionSemantics;
  s.limiter = c.limiter;
  s.staleTimeout = fromMs(c.staleTimeoutMs);
  s.frozenPositionsAreStale = c.frozenPositionsAreStale;
  s.travelMarginMm = c.travelMarginMm;
  s.directionHysteresisMm = c.directionHysteresisMm;
  s.offsetReadback = c.offsetReadback;
  s.plcZeroAfter = fromMs(c.plcZeroAfterMs.value_or(0.0));
  s.reconnectInitial = fromMs(c.reconnect.initialMs);
  s.reconnectMax = fromMs(c.reconnect.maxMs);
  return s;
}

}  // namespace volcomp::daemon
