#pragma once
/// The simulated machine behind the controller's registers, independent of any transport (the
/// Modbus server and a CAN node both drive it):
/// - the axes follow a Path; the programmed position q(t) is what the part program commands;
/// - the controller applies the compensation offsets o the daemon writes, immediately, so the
///   axes physically go to q + o; the position registers show q (`commanded` semantics) or q + o
///   (`actual`);
/// - a TRUE error model E(q) = p(q) - p0(q) (mm, workpiece frame), evaluated with the direction in
///   which each axis last moved, gives the tool-tip error:
///   uncompensated E(q), compensated p(q + o) - p0(q) = E(q + o) + o (p0 is linear in q), and
///   motion-induced: the compensated error minus E(q + o*) + o* of the ideal offset o* = -E(q + o*)
///   at the same instant (zero latency, true direction; the register count of the written offset
///   stays in it: 0.1 um counts leave ~0.05 um RMS);
/// - every write is recorded and checked against the configured limits, per axis, with the time
///   the controller measures between the writes it applies (|o| <= max_offset,
///   |o - o_applied| <= max_rate * (min(dt, cycle) + rate_tolerance), plus register rounding);
/// - faults (stall, link drop, exception replies, late or lost replies to writes that are
///   applied all the same, a client stopped between its read and its write, frozen registers,
///   feed hold, enable/homed/fault-ack) are set by commands and read by the transport.
/// Time is seconds on the caller's clock (monotonic); every method is thread-safe.

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <string>
#include <utility>
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
  /// Per axis X, Y, Z.
  Vec3 maxOffsetMm{kUnlimited, kUnlimited, kUnlimited};
  Vec3 maxRateMmS{kUnlimited, kUnlimited, kUnlimited};
  /// Timing jitter allowed in the rate check (the writer measures its dt when it sends, the
  /// controller when it applies).
  double rateToleranceS = 0.005;
  /// One register count of each offset output (mm): quantisation allowed in both checks.
  Vec3 quantumMm{};
  /// The writer's cycle period. A write may step from the applied offset by
  /// max_rate * (min(dt, cycle) + tolerance), dt the time since the previous write applied (the
  /// first write: one cycle): late cycles cannot bunch steps, and a gap (a stall, a lost link, a
  /// new session) allows one cycle's step at most. One step more plus loop::kReadbackResolutionMm
  /// when the controller changed the offsets itself (watchdog ramp) since the previous write.
  double cycleS = 0.01;
  static constexpr double kUnlimited = std::numeric_limits<double>::infinity();
};

struct MachineOptions {
  loop::PositionSemantics semantics = loop::PositionSemantics::Commanded;
  Limits limits;
  /// Offsets the controller applies at start (left over from an earlier run), mm.
  Vec3 initialOffsetMm{};
  /// Controller-side heartbeat watchdog: when the heartbeat has not changed for this long (counted
  /// from the start when nothing was written yet), the controller ramps the offsets to zero at
  /// `watchdogRampMmS`. 0 = no watchdog.
  double heartbeatTimeoutS = 0.0;
  double watchdogRampMmS = 1.0;
  /// Statistics start this long after the first write.
  double settleS = 0.0;
  /// The controller's own delay from receiving an offset to applying it at the axes (its PLC
  /// scan, its interpolation cycle), s. The registers, the read-back and the rate check see a
  /// write when it arrives; the axes (the error statistics, actual positions) this much later.
  double axisLatencyS = 0.0;
  /// The controller latches the positions once per scan of this length (s) and serves them
  /// until the next scan; 0 = the positions at the moment of each read.
  double positionScanS = 0.0;
  /// Stamp every sample with the time its positions were latched, in ticks of this length (s),
  /// 16 bits wrapping (a mapped timestamp register); 0 = no timestamp.
  double timestampTickS = 0.0;
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

/// What happens to the reply of one write request (the write itself is applied).
struct WriteReply {
  bool drop = false;    ///< never answered
  double delayS = 0.0;  ///< answered this late
};

/// A client to stop (SIGSTOP) before the reply to its next read request, and continue (SIGCONT)
/// after `seconds`: the process is stopped between its read and its write, deterministically.
struct ClientPause {
  int pid = 0;  ///< 0 = none
  double seconds = 0.0;
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
  /// The fate of the reply to the write request being handled (consumes a late-reply or no-reply
  /// fault).
  WriteReply takeWriteReply();
  /// A pause of the client to apply before answering the read request being handled (consumed).
  ClientPause takeClientPause();

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
  void setFaultAck(bool on);
  /// The X applied-offset read-back reports `mm` (a garbled reply) for durationS.
  void garbleReadback(double tS, double mm, double durationS);
  /// The next `count` write requests are applied and answered `delayS` late (after the client's
  /// response timeout, when longer).
  void lateReplies(double delayS, int count);
  /// The next `count` write requests are applied and never answered.
  void dropReplies(int count);
  /// Stops process `pid` before answering its next read request, for `seconds`.
  void pauseClient(int pid, double seconds);
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
  bool faultAck_ = false;
  double lateReplyS_ = 0.0;
  int lateReplies_ = 0;
  int droppedReplies_ = 0;
  ClientPause pause_;
  std::uint16_t sequence_ = 0;
  loop::AxisSample frozenSample_{};

  double stallUntil_ = 0.0, dropUntil_ = 0.0, exceptionUntil_ = 0.0, freezeUntil_ = 0.0,
         holdUntil_ = 0.0, garbleUntil_ = 0.0;
  double garbleMm_ = 0.0;
  int exceptionCode_ = 0;

  bool controllerChanged_ = false;  // the watchdog ramp moved applied_ since the last write
  bool anyWrite_ = false;
  double firstWriteT_ = 0.0;
  double lastWriteT_ = 0.0;
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
  std::uint64_t lateRepliesSent_ = 0, repliesDropped_ = 0, clientPauses_ = 0;
  /// The compensated error minus what the ideal offset (the true model solved at the true
  /// position and direction of the same instant) would leave: what the offsets' lag behind the
  /// motion, the direction tracking and the limiter add.
  /// motionSteady_: the samples more than three writer cycles (Limits::cycleS) away from any
  /// reversal of any axis, before or after it (the transient after a turn; and before it, where a
  /// daemon predicting the turn already blends the other direction in). A sample waits in
  /// steadyPending_ until it is that old, and is dropped if a reversal comes first.
  ErrorStatistics uncompensated_, compensated_, motion_, motionSteady_;
  std::deque<std::pair<double, Vec3>> steadyPending_;
  /// With axisLatencyS: applied_ since it last took effect at the axes, (time, value).
  std::deque<std::pair<double, Vec3>> appliedHistory_;
  Vec3 atAxesLocked(double tS);
  double lastReversalT_ = -std::numeric_limits<double>::infinity();
  double lastSampleT_ = -std::numeric_limits<double>::infinity();
};

}  // namespace volcomp::sim
