#include "volcomp/daemon/configuration.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

#include "volcomp/config/model_file.hpp"

namespace volcomp::daemon {
namespace {

std::chrono::nanoseconds fromMs(double ms) noexcept {
  return std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(ms * 1e6)));
}

}  // namespace

LoadedConfiguration loadConfiguration(const std::string& configPath) {
  LoadedConfiguration loaded;
  loaded.config = config::loadDaemonConfig(configPath);
  loaded.model = loadCompensationModel(loaded.config.modelPath);
  return loaded;
}

std::shared_ptr<loop::CompensationModel> loadCompensationModel(const std::string& path) {
  model::MachineModelSpec spec = config::loadMachineModelFile(path, "live compensation");
  std::string name = spec.name.empty() ? path : spec.name;
  return std::make_shared<loop::MachineModelCompensation>(model::MachineModel(std::move(spec)),
                                                          std::move(name));
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
