#pragma once
// Fakes for driving CompensationLoop without I/O or sleeping: a settable clock, a scripted
// controller port and a model returning a programmable offset. None allocates per call.

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "volcomp/loop/compensation_model.hpp"
#include "volcomp/loop/ports.hpp"

namespace volcomp::loop::testing {

class FakeClock final : public Clock {
 public:
  time_point now() const noexcept override { return now_; }
  void advance(std::chrono::nanoseconds d) noexcept { now_ += d; }

 private:
  time_point now_ = time_point(std::chrono::hours(1000));
};

/// Plays the controller: holds the inputs the loop reads and records what it writes. Applied
/// offsets follow the writes (a controller applying them at once), unless `holdApplied`.
class FakePort final : public ControllerPort {
 public:
  std::error_code connect() noexcept override {
    ++connectCalls;
    if (connectError) return connectError;
    connected_ = true;
    return {};
  }
  void disconnect() noexcept override { connected_ = false; }
  bool connected() const noexcept override { return connected_; }

  std::error_code read(AxisSample& out) noexcept override {
    ++readCalls;
    if (!connected_) return std::make_error_code(std::errc::not_connected);
    if (readError) return readError;
    out = sample;
    if (readback) {
      out.hasAppliedOffsets = true;
      out.appliedOffsetMm = applied;
    } else {
      out.hasAppliedOffsets = false;
    }
    if (semanticsActual) {
      // The controller's position register includes the applied offset.
      for (int k = 0; k < 3; ++k) out.positionMm[k] = sample.positionMm[k] + applied[k];
    }
    if (autoSequence) {
      ++sequence;
      out.hasSequence = true;
      out.sequence = sequence;
    }
    // After the controller answered: what happens before the loop writes (a pause, a ramp).
    if (afterRead) afterRead();
    return {};
  }

  std::error_code write(const OffsetCommand& command) noexcept override {
    ++writeCalls;
    if (duringWrite) duringWrite();
    if (!connected_) return std::make_error_code(std::errc::not_connected);
    if (applyFailedWrites && !holdApplied) applied = command.offsetMm;  // applied, answer lost
    if (writeError) return writeError;
    last = command;
    ++writes;
    if (history != nullptr) history->push_back(command);
    if (!holdApplied) applied = command.offsetMm;
    return {};
  }

  /// Simulates the transport going down (the next read/write fails with a link error).
  void dropLink() noexcept { connected_ = false; }

  AxisSample sample{{100.0, 50.0, -20.0}, true, true, false, {}, false, 0};
  bool readback = true;
  bool semanticsActual = false;
  bool autoSequence = false;
  bool holdApplied = false;
  /// A failed write (writeError) is applied all the same: its reply was late or lost.
  bool applyFailedWrites = false;
  /// Runs inside read() after the sample is taken (e.g. advance the clock: a stopped process).
  std::function<void()> afterRead;
  /// Runs inside write() before it returns (e.g. advance the clock: the transaction's time).
  std::function<void()> duringWrite;
  std::uint16_t sequence = 0;
  std::array<double, 3> applied{};
  std::error_code connectError;
  std::error_code readError;
  std::error_code writeError;
  std::optional<OffsetCommand> lastOrNone() const {
    return writes ? std::optional(last) : std::nullopt;
  }
  OffsetCommand last{};
  /// When set, every successful write is appended (tests that need the whole sequence).
  std::vector<OffsetCommand>* history = nullptr;
  int writes = 0;
  int writeCalls = 0;
  int readCalls = 0;
  int connectCalls = 0;

 private:
  bool connected_ = false;
};

/// Model with a programmable offset; records the positions it was evaluated at.
class FakeModel final : public CompensationModel {
 public:
  explicit FakeModel(std::array<double, 3> offsetMm = {0.01, -0.02, 0.03}) : offset_(offsetMm) {
    travel_[0] = std::array<double, 2>{0.0, 500.0};
    travel_[1] = std::array<double, 2>{0.0, 400.0};
    travel_[2] = std::array<double, 2>{-300.0, 0.0};
  }
  ModelOffset offset(const std::array<double, 3>& qMm,
                     const model::Directions& directions) noexcept override {
    lastQ = qMm;
    lastDirections = directions;
    ++calls;
    ModelOffset r;
    r.offsetMm = offset_;
    if (directions[0] == model::Direction::Negative) r.offsetMm[0] += negativeXShiftMm;
    r.converged = converged;
    return r;
  }
  const std::array<std::optional<std::array<double, 2>>, 3>& travelMm() const noexcept override {
    return travel_;
  }
  const std::string& name() const noexcept override { return name_; }

  void setOffset(std::array<double, 3> o) noexcept { offset_ = o; }
  bool converged = true;
  /// A bidirectional X table: this much more X offset while X moves negative.
  double negativeXShiftMm = 0.0;
  std::array<double, 3> lastQ{};
  model::Directions lastDirections{};
  int calls = 0;

 private:
  std::array<double, 3> offset_;
  std::array<std::optional<std::array<double, 2>>, 3> travel_{};
  std::string name_ = "fake";
};

}  // namespace volcomp::loop::testing
