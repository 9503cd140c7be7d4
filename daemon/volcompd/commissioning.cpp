#include "commissioning.hpp"

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <ostream>
#include <stdexcept>
#include <thread>

#include "volcomp/config/display_units.hpp"
#include "volcomp/loop/limiter.hpp"
#include "volcomp/loop/status.hpp"

namespace volcomp::volcompd {
namespace {

using Clock = std::chrono::steady_clock;
constexpr const char* kAxes = "XYZ";

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int) {
  gInterrupted = true;
}

// SIGINT/SIGTERM during the test end the hold early: the offset is still ramped out.
void catchInterrupts() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

/// Reads one consistent sample, retrying failed reads until `timeout` (a CAN link needs its first
/// complete set of frames; a PLC may answer a moment late).
std::error_code readSample(loop::ControllerPort& port, loop::AxisSample& sample,
                           std::chrono::milliseconds timeout) {
  const auto deadline = Clock::now() + timeout;
  std::error_code ec;
  do {
    if (!port.connected()) ec = port.connect();
    if (!ec) ec = port.read(sample);
    if (!ec) return {};
    if (Clock::now() >= deadline) break;
    std::this_thread::sleep_until(Clock::now() + std::chrono::milliseconds(20));
  } while (true);
  return ec;
}

/// Paces the test writes on absolute deadlines of the configured cycle period.
class Pacer {
 public:
  explicit Pacer(double periodMs)
      : period_(std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double, std::milli>(periodMs))),
        next_(Clock::now()) {}
  void wait() {
    next_ += period_;
    std::this_thread::sleep_until(next_);
  }

 private:
  Clock::duration period_;
  Clock::time_point next_;
};

struct TestRun {
  loop::LimiterState limiter;
  std::uint16_t heartbeat = 0;
  std::array<double, 3> lastWrittenMm{};
  std::error_code error;
};

// One cycle of the test: limiter step towards `targetMm`, write, read back.
bool testCycle(loop::ControllerPort& port, const config::DaemonConfig& config, TestRun& run,
               const std::array<double, 3>& targetMm, std::uint16_t status,
               loop::AxisSample& sample) {
  const loop::LimiterOutput limited =
      loop::limitStep(config.limiter, run.limiter, targetMm, config.cyclePeriodMs / 1000.0);
  loop::OffsetCommand command;
  command.offsetMm = limited.offsetMm;
  command.status =
      static_cast<std::uint16_t>(status | (limited.limited ? loop::status::kLimited : 0));
  command.heartbeat = ++run.heartbeat;
  if ((run.error = port.write(command))) return false;
  run.lastWrittenMm = limited.offsetMm;
  return !(run.error = port.read(sample));
}

bool atTarget(const TestRun& run, const std::array<double, 3>& targetMm) {
  for (int k = 0; k < 3; ++k) {
    if (run.limiter.offsetMm[k] != targetMm[k]) return false;
  }
  return true;
}

std::string signedMicrometres(double mm) {
  const std::string text = config::micrometres(mm);
  return (mm > 0 && text.front() != '-' && text.rfind("0 ", 0) != 0 ? "+" : "") + text;
}

int runTestOffset(loop::ControllerPort& port, const RawView& raw,
                  const config::DaemonConfig& config, const ProbeOptions& options,
                  const loop::AxisSample& before, std::ostream& out) {
  const TestOffset& test = *options.testOffset;
  const char axis = kAxes[test.axis];
  if (!before.enable || !before.homed) {
    out << "test-offset: not run: the controller's " << (!before.enable ? "enable" : "homed")
        << " input is off; the daemon writes offsets only while compensation is enabled and the "
           "axes are homed\n";
    return 1;
  }
  if (before.hasAppliedOffsets) {
    for (int k = 0; k < 3; ++k) {
      if (std::abs(before.appliedOffsetMm[k]) > 1e-6) {
        out << "test-offset: not run: the controller applies "
            << signedMicrometres(before.appliedOffsetMm[k]) << " on " << kAxes[k]
            << " now; is volcompd running? Stop it (its stop ramps the offsets out) first\n";
        return 1;
      }
    }
  } else {
    // Without a read-back the applied offsets are known to be zero only after the PLC's
    // watchdog removed whatever an earlier run left, as at the daemon's start.
    const double waitMs = config.plcZeroAfterMs.value_or(0.0);
    out << "test-offset: no read-back mapped: waiting " << waitMs
        << " ms (plc_zero_after_ms) for the PLC to have removed earlier offsets\n";
    std::this_thread::sleep_until(Clock::now() +
                                  std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double, std::milli>(waitMs)));
  }

  catchInterrupts();
  std::array<double, 3> target{};
  target[test.axis] = test.offsetMm;
  TestRun run;
  loop::AxisSample sample = before;
  Pacer pacer(config.cyclePeriodMs);
  const auto start = Clock::now();
  out << "test-offset: " << axis << ' ' << signedMicrometres(test.offsetMm)
      << " through the limiter (" << config::micrometres(config.limiter.axes[test.axis].maxRateMmS)
      << "/s), held " << options.holdS << " s, then ramped out\n";

  // Ramp in, then hold: the heartbeat must keep moving or the PLC's watchdog drops the offset.
  std::optional<double> readBackAfterS;
  const auto holdEnd = [&] {
    return Clock::now() - start >=
           std::chrono::duration<double>(options.holdS) +
               std::chrono::duration<double>(std::abs(test.offsetMm) /
                                             config.limiter.axes[test.axis].maxRateMmS);
  };
  while (!gInterrupted && !holdEnd()) {
    if (!testCycle(port, config, run, target, loop::status::kActive, sample)) break;
    if (!readBackAfterS && atTarget(run, target) && sample.hasAppliedOffsets &&
        std::abs(sample.appliedOffsetMm[test.axis] - test.offsetMm) <
            1e-6 + std::abs(test.offsetMm) * 1e-3) {
      readBackAfterS = std::chrono::duration<double>(Clock::now() - start).count();
    }
    pacer.wait();
  }
  const loop::AxisSample held = sample;
  const double heldWrittenMm = run.lastWrittenMm[test.axis];
  const bool reached = atTarget(run, target);
  if (!run.error) {
    out << "written (last write):\n";
    raw.printOutputs(out);
    out << "read back (last read):\n";
    raw.printInputs(out);
  }

  // Ramp out through the limiter, then zero with status 0, as the daemon's stop does.
  const std::error_code heldError = run.error;
  run.error = {};
  const std::array<double, 3> zero{};
  for (int guard = 0; !run.error && !loop::limiterAtZero(run.limiter) && guard < 1000000; ++guard) {
    pacer.wait();
    testCycle(port, config, run, zero, loop::status::kStopping, sample);
  }
  if (!run.error) testCycle(port, config, run, zero, 0, sample);
  const bool rampedOut = !run.error && loop::limiterAtZero(run.limiter);

  // The report.
  out << "report      axis " << axis << ", offset " << signedMicrometres(test.offsetMm) << '\n';
  if (heldError) {
    out << "  FAILED: a transaction failed while the offset was applied: " << heldError.message()
        << '\n';
  }
  out << "  written   " << signedMicrometres(heldWrittenMm)
      << " while held (reached the target: " << (reached ? "yes" : "no") << ")\n";
  int status = heldError || !reached ? 1 : 0;
  if (held.hasAppliedOffsets) {
    const double back = held.appliedOffsetMm[test.axis];
    out << "  read back " << signedMicrometres(back) << " (applied_offset." << axis << ")";
    if (readBackAfterS) {
      out << ", equal to the target " << config::significant(*readBackAfterS)
          << " s after the start\n";
    } else {
      out << ": DIFFERENT from the target; ";
      if (std::abs(back + test.offsetMm) < 1e-6 + std::abs(test.offsetMm) * 1e-3) {
        out << "the sign is inverted: check the sign of offset." << axis << " and applied_offset."
            << axis << '\n';
      } else if (std::abs(back) < 1e-9) {
        out << "the controller does not apply it (enable, PLC logic, heartbeat watchdog?)\n";
      } else {
        out << "check the scale (counts_per_mm) and byte order of offset." << axis
            << " and applied_offset." << axis << '\n';
      }
      status = 1;
    }
  } else {
    out << "  read back not mapped: compare on the controller (its external offset of " << axis
        << " should show " << signedMicrometres(test.offsetMm) << ")\n";
  }
  for (int k = 0; k < 3; ++k) {
    out << (k == 0 ? "  position  moved " : ", ") << kAxes[k] << ' '
        << signedMicrometres(held.positionMm[k] - before.positionMm[k]);
  }
  out << " while the offset was applied ("
      << (config.positionSemantics == loop::PositionSemantics::Actual
              ? "actual positions: a machine at rest moves by the offset, +5 um -> +5 um"
              : "commanded positions: they do not include the offset")
      << ")\n";
  out << "  ramp-out  "
      << (rampedOut ? "zero written with status 0" : "FAILED: " + run.error.message())
      << (gInterrupted ? " (interrupted)" : "") << '\n';
  if (!rampedOut) status = 1;
  out << "  on the machine: with the tool at rest, +" << axis
      << " offset moves the tool by + along the machine's " << axis
      << " axis relative to the workpiece (docs/commissioning.md)\n";
  return status;
}

}  // namespace

TestOffset parseTestOffset(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(
        "--test-offset: expected AXIS:VALUE[um|mm|nm], e.g. X:5um, got \"" + text + "\" (" + why +
        ")");
  };
  const std::size_t colon = text.find(':');
  if (colon != 1) throw bad("the axis X, Y or Z, then ':'");
  const char a = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  if (a != 'X' && a != 'Y' && a != 'Z') throw bad("the axis X, Y or Z");
  std::string rest = text.substr(2);
  rest.erase(std::remove(rest.begin(), rest.end(), ' '), rest.end());
  double factor = 1e-3;
  for (const auto& [suffix, f] :
       {std::pair{"um", 1e-3}, std::pair{"mm", 1.0}, std::pair{"nm", 1e-6}}) {
    const std::string s = suffix;
    if (rest.size() > s.size() && rest.compare(rest.size() - s.size(), s.size(), s) == 0) {
      factor = f;
      rest.erase(rest.size() - s.size());
      break;
    }
  }
  if (!rest.empty() && rest.front() == '+') rest.erase(0, 1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
  if (ec != std::errc() || end != rest.data() + rest.size() || rest.empty() ||
      !std::isfinite(value)) {
    throw bad("a number");
  }
  if (value == 0.0) throw bad("a value other than 0");
  return {a - 'X', value * factor};
}

int runProbe(const config::DaemonConfig& config, const ProbeOptions& options, std::ostream& out) {
  if (options.testOffset && std::abs(options.testOffset->offsetMm) >
                                config.limiter.axes[options.testOffset->axis].maxOffsetMm) {
    out << "test-offset: " << signedMicrometres(options.testOffset->offsetMm)
        << " is beyond limiter.max_offset_mm ("
        << config::micrometres(config.limiter.axes[options.testOffset->axis].maxOffsetMm)
        << "); a sign check needs a few um\n";
    return 2;
  }
  ProbeTransport transport = makeProbeTransport(config.transport, config.file);
  out << "probe       " << config::transportEndpoint(config.transport) << ": "
      << transport.raw->readDescription() << '\n';
  loop::AxisSample sample;
  if (const std::error_code ec = readSample(*transport.port, sample, std::chrono::seconds(3))) {
    out << "probe       FAILED: " << ec.message() << " ("
        << config::transportEndpoint(config.transport) << ")\n";
    return 1;
  }
  out << "read        one consistent sample:\n";
  transport.raw->printInputs(out);
  int status = 0;
  if (options.testOffset) {
    status = runTestOffset(*transport.port, *transport.raw, config, options, sample, out);
  } else {
    out << "written     nothing (--test-offset AXIS:VALUE writes one small offset)\n";
  }
  transport.port->disconnect();
  return status;
}

}  // namespace volcomp::volcompd
