#pragma once
/// The simulated machine behind the controller's registers, independent of any transport (the
/// Modbus server and a CAN node both drive it):
/// - the axes follow a Path; the programmed position q(t) is what the part program commands;
/// - the controller applies the compensation offsets o the daemon writes, immediately, so the
///   axes physically go to q + o; the position registers show q (`commanded` semantics) or q + o
///   (`actual`);
/// - a TRUE error model E(q) = p(q) - p0(q) (mm, workpiece frame), evaluated with the direction in
///   which each axis last moved, gives the tool-tip error:
///   uncompensated E(q), compensated p(q + o) - p0(q) = E(q + o) + o (p0 is linear in q);
/// - every write is recorded and checked against the configured limits (|o| <= max_offset,
///   |o - o_prev| <= max_rate * (max(dt, cycle) + rate_tolerance), plus register rounding);
/// - faults (stall, link drop, exception replies, frozen registers, feed hold, enable/homed) are
///   set by commands and read by the transport.
/// Time is seconds on the caller's clock (monotonic); every method is thread-safe.

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volcomp/config/daemon_config.hpp"
#include "volcomp/loop/ports.hpp"
#include "volcomp/sim/path.hpp"

namespace volcomp::sim {

/// Direction in which each axis last moved: -1, +1, or 0 (not moved yet).
using MotionDirections = std::array<int, 3>;

/// True tool-tip position error E(q) (mm) at axis position q (mm), for axes that last moved in
/// the given directions (a bidirectional model picks its curves by them).
using ErrorFunction = std::function<Vec3(const Vec3&, const MotionDirections&)>;

struct Limits {
  double maxOffsetMm = std::numeric_limits<double>::infinity();
  double maxRateMmS = std::numeric_limits<double>::infinity();
  /// Timing jitter allowed in the rate check (the writer's dt may differ from the observed one).
  double rateToleranceS = 0.005;
  /// One register count of each offset output (mm): quantisation allowed in both checks.
  Vec3 quantumMm{};
  /// The writer's cycle period: any write (the first of a session included, and the first after
  /// a gap) may step from the applied offset by one limiter step, max_rate * (cycle + tolerance);
  /// by two steps plus loop::kReadbackResolutionMm when the controller changed the offsets itself
  /// (watchdog ramp) since the previous write.
  double cycleS = 0.01;
};

struct MachineOptions {
  loop::PositionSemantics semantics = loop::PositionSemantics::Commanded;
  Limits limits;
  /// Offsets the controller applies at start (left over from an earlier run), mm.
  Vec3 initialOffsetMm{};
  /// Controller-side heartbeat watchdog: when the heartbeat has not changed for this long (and at
  /// least one write was seen), the controller ramps the offsets to zero at `watchdogRampMmS`.
  /// 0 = no watchdog.
  double heartbeatTimeoutS = 0.0;
  double watchdogRampMmS = 1.0;
  /// Statistics start this long after the first write.
  double settleS = 0.0;
  bool enable = true;
  bool homed = true;
  /// Keep every WriteRecord for writes() (for --record); otherwise only counters grow.
  bool keepWrites = true;
};

/// One write as the controller saw it.
struct WriteRecord {
  double timeS = 0.0;
  Vec3 offsetMm{};
  std::uint16_t status = 0;
  std::uint16_t heartbeat = 0;
  bool partial = false;    ///< the write did not cover the whole output block
  bool violation = false;  ///< broke max_offset or max_rate
};

/// What the transport should do with requests right now.
struct TransportFault {
  bool stall = false;     ///< receive requests, never answer
  bool linkDown = false;  ///< drop the connection and refuse new ones (RTU: silent)
  int exceptionCode = 0;  ///< answer every request with this Modbus exception (0 = none)
};

struct ErrorStatistics {
  std::uint64_t samples = 0;
  double sumSqNorm = 0.0;
  double maxNorm = 0.0;
  Vec3 sumSqAxis{};
  Vec3 maxAbsAxis{};
  void add(const Vec3& e) noexcept;
};

class Machine {
 public:
  Machine(Path path, ErrorFunction trueError, MachineOptions options);

  // Transport side --------------------------------------------------------------------------
  /// The inputs the registers show at time t (positions per semantics, flags, applied offsets,
  /// life counter).
  loop::AxisSample inputs(double tS);
  /// The controller received outputs; `partial` when not all output registers were written.
  void onWrite(double tS, const loop::OffsetCommand& command, bool partial = false);
  /// A client connected (TCP accept); the rate check of its first write uses this time.
  void onSessionStart(double tS);
  TransportFault transportFault(double tS);
  /// Counts a request the transport answered (or dropped, or answered with an exception).
  void countRequest(bool answered, bool exception);

  // Simulation side -------------------------------------------------------------------------
  /// Advances the machine to t and samples the tool-tip error (call at a fixed rate).
  void sample(double tS);

  // Faults (durationS <= 0: until resume()) ----------------------------------------------------
  void stall(double tS, double durationS);
  void dropLink(double tS, double durationS);
  void exception(double tS, int code, double durationS);
  void freeze(double tS, double durationS);
  void hold(double tS, double durationS);
  void setEnable(bool on);
  void setHomed(bool on);
  void resume();

  /// The report (see volcomp-sim's documentation for the keys).
  nlohmann::json report(double tS) const;
  std::vector<WriteRecord> writes() const;
  Vec3 appliedOffsetMm() const;
  Vec3 programmedPositionMm() const;

 private:
  void advanceLocked(double tS);
  static bool activeAt(double untilS, double tS) noexcept { return tS < untilS; }

  const Path path_;
  const ErrorFunction trueError_;
  const MachineOptions options_;
  mutable std::mutex mutex_;

  double lastT_ = 0.0;
  bool started_ = false;
  double pathTimeS_ = 0.0;
  Vec3 programmed_{};
  MotionDirections directions_{};
  Vec3 applied_{};
  bool enable_ = true;
  bool homed_ = true;
  std::uint16_t sequence_ = 0;
  loop::AxisSample frozenSample_{};

  double stallUntil_ = 0.0, dropUntil_ = 0.0, exceptionUntil_ = 0.0, freezeUntil_ = 0.0,
         holdUntil_ = 0.0;
  int exceptionCode_ = 0;

  bool controllerChanged_ = false;  // the watchdog ramp moved applied_ since the last write
  bool anyWrite_ = false;
  double firstWriteT_ = 0.0;
  std::uint16_t lastHeartbeat_ = 0;
  double lastHeartbeatChangeT_ = 0.0;
  bool watchdogTripped_ = false;
  std::uint64_t watchdogTrips_ = 0;

  std::vector<WriteRecord> writes_;
  std::uint64_t writeCount_ = 0;
  std::uint64_t violations_ = 0, offsetViolations_ = 0, rateViolations_ = 0, partialWrites_ = 0;
  std::array<std::uint64_t, 3> axisViolations_{};
  std::string firstViolation_;
  Vec3 maxAbsWrittenMm_{};
  std::uint64_t sessions_ = 0, requests_ = 0, unanswered_ = 0, exceptionsSent_ = 0;
  ErrorStatistics uncompensated_, compensated_;
};

}  // namespace volcomp::sim
