#include "volcomp/daemon/configuration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <utility>

#include "volcomp/config/calibration_record.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/model_file.hpp"
#include "volcomp/config/model_plausibility.hpp"
#include "volcomp/config/transport_limits.hpp"

namespace volcomp::daemon {
namespace {

std::chrono::nanoseconds fromMs(double ms) noexcept {
  return std::chrono::nanoseconds(static_cast<std::int64_t>(std::llround(ms * 1e6)));
}

std::string triple(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << '(' << v.x() + 0.0 << ", " << v.y() + 0.0 << ", " << v.z() + 0.0 << ')';
  return out.str();
}

// The daemon compensates for the model's own tool: one that the calibration never measured
// (further than the tolerance outside the measured tools' hull) extrapolates the lever arms.
std::optional<std::string> farToolWarning(const config::ModelDocument& document,
                                          const Eigen::Vector3d& toolMm, const std::string& path) {
  if (!document.calibration) return std::nullopt;
  const std::optional<double> distance = config::toolDistanceMm(*document.calibration, toolMm);
  if (!distance || *distance <= config::kCalibratedToolToleranceMm) return std::nullopt;
  std::ostringstream out;
  out << "model " << path << ": its tool " << triple(toolMm) << " mm is "
      << std::round(*distance * 10.0) / 10.0
      << " mm outside the tools the model was calibrated with, ";
  for (std::size_t i = 0; i < document.calibration->toolsMm.size(); ++i) {
    out << (i > 0 ? "; " : "") << triple(document.calibration->toolsMm[i]);
  }
  out << " mm: errors that act through the tool's lever arms are extrapolated";
  return out.str();
}

}  // namespace

LoadedConfiguration loadConfiguration(const std::string& configPath) {
  LoadedConfiguration loaded;
  loaded.config = config::loadDaemonConfig(configPath);
  loaded.model = loadCompensationModel(loaded.config.modelPath,
                                       config::offsetBoundOf(loaded.config), &loaded.warnings);
  return loaded;
}

std::shared_ptr<loop::CompensationModel> loadCompensationModel(
    const std::string& path, const std::optional<config::OffsetBound>& bound,
    std::vector<std::string>* warnings) {
  config::ModelDocument document = config::loadModelFile(path);
  auto* spec = std::get_if<model::MachineModelSpec>(&document.spec);
  if (spec == nullptr) {
    throw config::ConfigError(path, "chain",
                              "the daemon compensates 3-axis machine models; a D-H chain file "
                              "cannot be used for live compensation");
  }
  if (warnings != nullptr) {
    if (auto warning = farToolWarning(document, spec->toolMm, path)) {
      warnings->push_back(std::move(*warning));
    }
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
  s.readToWriteMax = fromMs(c.readToWriteMaxMs);
  s.saturationWarning = fromMs(c.saturationWarningMs);
  s.saturationFault = fromMs(c.saturationFaultMs);
  s.faultLatch = c.faultLatch;
  s.latencyCompensation = c.latencyCompensation;
  s.controllerLatency = fromMs(c.controllerLatencyMs);
  // A read-back of what was written may differ by one count of its register.
  s.readbackResolutionMm =
      std::max(loop::kReadbackResolutionMm, config::readbackCountMm(c.transport));
  s.reconnectInitial = fromMs(c.reconnect.initialMs);
  s.reconnectMax = fromMs(c.reconnect.maxMs);
  return s;
}

}  // namespace volcomp::daemon
