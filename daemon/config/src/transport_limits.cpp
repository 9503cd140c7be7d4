#include "volcomp/config/transport_limits.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>
#include <variant>

#include "volcomp/config/config_error.hpp"
#include "volcomp/format/numbers.hpp"
#include "volcomp/modbus/register_plan.hpp"

namespace volcomp::config {
namespace {

constexpr const char* kAxes[] = {"X", "Y", "Z"};

/// Largest raw count of an integer register type, and whether it holds negative values.
struct RawRange {
  double max;
  bool isSigned;
  bool isFloat;
  const char* name;
};

RawRange rangeOf(modbus::RegisterType type) noexcept {
  switch (type) {
    case modbus::RegisterType::Int16:
      return {32767.0, true, false, "int16"};
    case modbus::RegisterType::Uint16:
      return {65535.0, false, false, "uint16"};
    case modbus::RegisterType::Int32:
      return {2147483647.0, true, false, "int32"};
    case modbus::RegisterType::Uint32:
      return {4294967295.0, false, false, "uint32"};
    case modbus::RegisterType::Float32:
      return {3.4e38, true, true, "float32"};
    case modbus::RegisterType::Float64:
      return {1.7e308, true, true, "float64"};
  }
  return {0.0, false, false, "?"};
}

void checkRegister(const DaemonConfig& c, const modbus::ValueRegister& r, std::size_t axis,
                   const std::string& keyPath) {
  const double maxOffset = c.limiter.axes[axis].maxOffsetMm;
  const RawRange range = rangeOf(r.format.type);
  if (range.isFloat) return;
  if (!range.isSigned) {
    throw ConfigError(c.file, keyPath,
                      std::string("a ") + range.name + " register holds no negative offset; " +
                          "offsets are +-" + format::general(maxOffset) +
                          " mm (limiter.max_offset_mm, " + kAxes[axis] +
                          "): use int16, int32 or a float type");
  }
  const double holdsMm = range.max / r.format.countsPerMm;
  if (maxOffset > holdsMm) {
    throw ConfigError(c.file, keyPath,
                      std::string("an ") + range.name + " at " +
                          format::general(r.format.countsPerMm) + " counts/mm holds +-" +
                          format::general(holdsMm) + " mm, less than limiter.max_offset_mm " +
                          format::general(maxOffset) + " mm (" + kAxes[axis] +
                          "): use a wider type or fewer counts_per_mm");
  }
}

void checkSignal(const DaemonConfig& c, const can::SignalSpec& s, std::size_t axis,
                 const std::string& keyPath) {
  const double maxOffset = c.limiter.axes[axis].maxOffsetMm;
  double lo = -INFINITY, hi = INFINITY;
  if (s.valueType == can::ValueType::Signed || s.valueType == can::ValueType::Unsigned) {
    const double span = std::ldexp(1.0, static_cast<int>(s.length));
    const double rawLo = s.valueType == can::ValueType::Signed ? -span / 2.0 : 0.0;
    const double rawHi = s.valueType == can::ValueType::Signed ? span / 2.0 - 1.0 : span - 1.0;
    lo = std::min(rawLo * s.scale, rawHi * s.scale) + s.offset;
    hi = std::max(rawLo * s.scale, rawHi * s.scale) + s.offset;
  }
  if (s.minimum < s.maximum) {
    lo = std::max(lo, s.minimum);
    hi = std::min(hi, s.maximum);
  }
  if (lo > -maxOffset || hi < maxOffset) {
    throw ConfigError(c.file, keyPath,
                      "signal " + s.name + " holds [" + format::general(lo) + ", " +
                          format::general(hi) + "] mm, not +-" + format::general(maxOffset) +
                          " mm (limiter.max_offset_mm, " + kAxes[axis] +
                          "): widen it or change its scale");
  }
}

void checkModbus(const DaemonConfig& c, const modbus::ModbusSettings& m) {
  for (std::size_t k = 0; k < 3; ++k) {
    checkRegister(c, m.registers.offset[k], k,
                  std::string("transport.registers.offset.") + kAxes[k]);
    if (m.registers.appliedOffset) {
      checkRegister(c, (*m.registers.appliedOffset)[k], k,
                    std::string("transport.registers.applied_offset.") + kAxes[k]);
    }
  }
  // A server never waits for the master inside a cycle: its reads and writes are copies.
  if (m.role == modbus::ModbusRole::Server) return;
  // A cycle reads each input table once and writes once (FC23: the holding read rides on the
  // write); each transaction may wait response_timeout_ms.
  const modbus::RegisterPlan plan = modbus::planRegisters(m.registers);
  const bool fc23 = m.registers.fc23 && plan.holdingRead.count > 0;
  const int transactions =
      1 + (plan.inputRead.count > 0 ? 1 : 0) + (plan.holdingRead.count > 0 && !fc23 ? 1 : 0);
  const double blockedMs = transactions * m.responseTimeoutMs;
  if (blockedMs > c.serviceWatchdogMs / 2.0) {
    throw ConfigError(
        c.file, "transport.response_timeout_ms",
        "a cycle may wait " + std::to_string(transactions) + " x " +
            format::general(m.responseTimeoutMs) + " ms = " + format::general(blockedMs) +
            " ms for its transactions, more than half the service watchdog (" +
            format::general(c.serviceWatchdogMs) +
            " ms, service_watchdog_ms = WatchdogSec of the unit): a slow controller would get "
            "the daemon restarted. Use at most " +
            format::general(std::floor(c.serviceWatchdogMs / 2.0 / transactions)) +
            " ms, or raise WatchdogSec in a drop-in and service_watchdog_ms here");
  }
}

void checkCan(const DaemonConfig& c, const can::CanLayout& layout) {
  for (const can::FrameLayout& frame : layout.outputFrames) {
    for (const can::FieldSignal& s : frame.signals) {
      const auto k =
          static_cast<std::size_t>(s.field) - static_cast<std::size_t>(can::Field::OffsetX);
      if (k < 3) checkSignal(c, s.spec, k, std::string("transport.outputs.offset.") + kAxes[k]);
    }
  }
  for (const can::FrameLayout& frame : layout.inputFrames) {
    for (const can::FieldSignal& s : frame.signals) {
      const auto k =
          static_cast<std::size_t>(s.field) - static_cast<std::size_t>(can::Field::AppliedX);
      if (k < 3) {
        checkSignal(c, s.spec, k, std::string("transport.inputs.applied_offset.") + kAxes[k]);
      }
    }
  }
  const double responseMs =
      std::chrono::duration<double, std::milli>(layout.responseTimeout).count();
  if (layout.trigger == can::Trigger::Sync && responseMs > c.serviceWatchdogMs / 2.0) {
    throw ConfigError(c.file, "transport.response_timeout_ms",
                      "a cycle may wait " + format::general(responseMs) +
                          " ms for the input frames, more than half the service watchdog (" +
                          format::general(c.serviceWatchdogMs) +
                          " ms, service_watchdog_ms = WatchdogSec of the unit)");
  }
}

double countOf(const modbus::ValueRegister& r) noexcept {
  return rangeOf(r.format.type).isFloat ? 0.0 : 1.0 / r.format.countsPerMm;
}

}  // namespace

double readbackCountMm(const TransportSettings& transport) noexcept {
  double count = 0.0;
  if (const auto* m = std::get_if<modbus::ModbusSettings>(&transport)) {
    if (m->registers.appliedOffset) {
      for (const auto& r : *m->registers.appliedOffset) count = std::max(count, countOf(r));
    }
  } else if (const auto* layout = std::get_if<can::CanLayout>(&transport)) {
    for (const can::FrameLayout& frame : layout->inputFrames) {
      for (const can::FieldSignal& s : frame.signals) {
        const auto k =
            static_cast<std::size_t>(s.field) - static_cast<std::size_t>(can::Field::AppliedX);
        const bool integer = s.spec.valueType == can::ValueType::Signed ||
                             s.spec.valueType == can::ValueType::Unsigned;
        if (k < 3 && integer) count = std::max(count, std::abs(s.spec.scale));
      }
    }
  }
  return count;
}

void checkTransportLimits(const DaemonConfig& c) {
  std::visit(
      [&](const auto& settings) {
        using T = std::decay_t<decltype(settings)>;
        if constexpr (std::is_same_v<T, modbus::ModbusSettings>) {
          checkModbus(c, settings);
        } else if constexpr (std::is_same_v<T, can::CanLayout>) {
          checkCan(c, settings);
        }
        // LinuxCNC HAL pins carry doubles and the cycle does not block on a peer: nothing to
        // check.
      },
      c.transport);
}

}  // namespace volcomp::config
