#include <algorithm>
#include <bitset>
#include <cmath>

#include "can_section.hpp"
#include "volcomp/can/dbc.hpp"
#include "volcomp/config/can_config.hpp"
#include "volcomp/config/dbc_file.hpp"
#include "volcomp/format/numbers.hpp"

namespace volcomp::config {
namespace {

using can::ByteOrder;
using can::CanLayout;
using can::DbcDatabase;
using can::DbcMessage;
using can::Field;
using can::FieldSignal;
using can::Frame;
using can::FrameLayout;
using can::SignalSpec;
using can::ValueType;

constexpr Field fieldAt(Field first, std::size_t axis) noexcept {
  return static_cast<Field>(static_cast<std::size_t>(first) + axis);
}

/// Payload bit numbers (DBC numbering: byte * 8 + bit, bit 0 = LSB) the signal occupies.
std::bitset<8 * can::kFdMaxLength> occupiedBits(const SignalSpec& spec) {
  std::bitset<8 * can::kFdMaxLength> bits;
  const unsigned msbLinear = (spec.startBit / 8) * 8 + (7 - spec.startBit % 8);
  for (unsigned i = 0; i < spec.length; ++i) {
    if (spec.byteOrder == ByteOrder::Intel) {
      bits.set(spec.startBit + i);
    } else {
      const unsigned p = msbLinear + i;
      bits.set((p / 8) * 8 + (7 - p % 8));
    }
  }
  return bits;
}

class Resolver {
 public:
  explicit Resolver(const CanSection& c) : c_(c) {
    if (!c.dbcPath.empty()) dbc_ = readDbcFile(c.dbcPath);
    layout_.interfaceName = c.interfaceName;
    layout_.fd = c.fd;
    layout_.bitrateSwitch = c.bitrateSwitch;
    layout_.trigger = c.trigger;
    layout_.staleTimeout =
        std::chrono::microseconds(static_cast<std::int64_t>(std::llround(c.staleTimeoutMs * 1e3)));
    layout_.responseTimeout = std::chrono::microseconds(
        static_cast<std::int64_t>(std::llround(c.responseTimeoutMs * 1e3)));
  }

  CanLayout run() {
    for (std::size_t i = 0; i < 3; ++i) add(fieldAt(Field::PositionX, i), c_.position[i], true);
    add(Field::Enable, c_.enable, true);
    add(Field::Homed, c_.homed, true);
    if (c_.appliedOffset) {
      layout_.hasAppliedOffsets = true;
      for (std::size_t i = 0; i < 3; ++i)
        add(fieldAt(Field::AppliedX, i), (*c_.appliedOffset)[i], true);
    }
    for (const CanSignalRef& s : c_.sequence) add(Field::Sequence, s, true);
    layout_.hasSequence = !c_.sequence.empty();
    for (std::size_t i = 0; i < 3; ++i) add(fieldAt(Field::OffsetX, i), c_.offset[i], false);
    add(Field::Status, c_.status, false);
    add(Field::Heartbeat, c_.heartbeat, false);
    finish();
    return std::move(layout_);
  }

 private:
  [[noreturn]] void fail(const std::string& keyPath, const std::string& message) const {
    throw ConfigError(c_.file, keyPath, message);
  }

  static std::string where(const CanSignalRef& s) {
    return s.dbcName.empty() ? std::string() : "DBC signal " + s.dbcName + ": ";
  }

  SignalSpec toSpec(const CanSignalRef& s, std::size_t& dbcLength) const {
    dbcLength = 0;
    if (!s.dbcName.empty()) {
      if (!dbc_) fail(s.keyPath + ".dbc", "a DBC signal is referenced but no \"dbc\" file is set");
      const auto found = dbc_->find(s.dbcName);
      if (found.empty()) fail(s.keyPath + ".dbc", "no signal " + s.dbcName + " in " + c_.dbcPath);
      if (found.size() > 1)
        fail(s.keyPath + ".dbc",
             "signal name " + s.dbcName + " is ambiguous in the DBC; write it as Message.Signal");
      if (!found.front()->multiplexer.empty())
        fail(s.keyPath + ".dbc", "multiplexed DBC signals are not supported");
      const DbcMessage* message =
          dbc_->message(found.front()->spec.frameId, found.front()->spec.extended);
      dbcLength = message ? message->length : 0;
      return found.front()->spec;
    }
    return s.spec;
  }

  void add(Field field, const CanSignalRef& s, bool input) {
    std::size_t dbcLength = 0;
    const SignalSpec spec = toSpec(s, dbcLength);
    const std::string prefix = where(s);
    if (const std::string problem = layoutProblem(spec); !problem.empty())
      fail(s.keyPath, prefix + problem);
    const std::size_t maxLength = c_.fd ? can::kFdMaxLength : can::kClassicMaxLength;
    if (bytesNeeded(spec) > maxLength)
      fail(s.keyPath, prefix + "signal needs " + std::to_string(bytesNeeded(spec)) +
                          " bytes, more than a " + (c_.fd ? "CAN FD" : "classical CAN") +
                          " frame holds (" + std::to_string(maxLength) + ")");
    if (dbcLength > maxLength)
      fail(s.keyPath, prefix + "the DBC message is " + std::to_string(dbcLength) +
                          " bytes long, which needs \"fd\": true");
    const bool integer = spec.valueType == ValueType::Unsigned;
    const bool plainCounter = integer && spec.scale == 1.0 && spec.offset == 0.0;
    if (field == Field::Status && (!plainCounter || spec.length < 16))
      fail(s.keyPath, prefix +
                          "the status word needs an unsigned signal of at least 16 bits "
                          "with scale 1 and offset 0");
    if ((field == Field::Heartbeat || field == Field::Sequence) && !plainCounter)
      fail(s.keyPath, prefix + "a counter needs an unsigned signal with scale 1 and offset 0");

    std::vector<FrameLayout>& frames = input ? layout_.inputFrames : layout_.outputFrames;
    auto& other = input ? layout_.outputFrames : layout_.inputFrames;
    for (const FrameLayout& f : other)
      if (f.id == spec.frameId && f.extended == spec.extended)
        fail(s.keyPath, prefix + "frame " + format::hexId(spec.frameId, spec.extended) +
                            " cannot be both an input and an output");
    auto it = std::find_if(frames.begin(), frames.end(), [&](const FrameLayout& f) {
      return f.id == spec.frameId && f.extended == spec.extended;
    });
    if (it == frames.end()) {
      frames.push_back(FrameLayout{spec.frameId, spec.extended, 0, {}});
      keyPaths_[input].emplace_back();
      it = frames.end() - 1;
    }
    const auto index = static_cast<std::size_t>(it - frames.begin());
    const auto bits = occupiedBits(spec);
    for (std::size_t j = 0; j < it->signals.size(); ++j) {
      if ((occupiedBits(it->signals[j].spec) & bits).any())
        fail(s.keyPath, prefix + "overlaps " + keyPaths_[input][index][j] + " in frame " +
                            format::hexId(spec.frameId, spec.extended));
      if (field == Field::Sequence && it->signals[j].field == Field::Sequence)
        fail(s.keyPath, prefix + "frame " + format::hexId(spec.frameId, spec.extended) +
                            " already carries a sequence counter");
    }
    it->length = std::max({it->length, bytesNeeded(spec), dbcLength});
    it->signals.push_back(FieldSignal{field, spec});
    keyPaths_[input][index].push_back(s.keyPath);
  }

  void finish() {
    for (FrameLayout& f : layout_.outputFrames) f.length = can::validLengthAtLeast(f.length, c_.fd);
    if (c_.trigger == can::Trigger::Broadcast && layout_.inputFrames.size() > 1) {
      for (std::size_t i = 0; i < layout_.inputFrames.size(); ++i) {
        const FrameLayout& f = layout_.inputFrames[i];
        const bool hasCounter = std::any_of(f.signals.begin(), f.signals.end(), [](const auto& s) {
          return s.field == Field::Sequence;
        });
        if (!hasCounter)
          fail(c_.keyPath + ".inputs.sequence",
               "with the broadcast trigger and " + std::to_string(layout_.inputFrames.size()) +
                   " input frames, every input frame needs a sequence counter; frame " +
                   format::hexId(f.id, f.extended) + " has none");
      }
    }
    if (c_.sync) {
      Frame sync;
      sync.id = c_.sync->id;
      sync.extended = c_.sync->extended;
      sync.fd = c_.fd && c_.sync->data.size() > can::kClassicMaxLength;
      sync.length = static_cast<std::uint8_t>(c_.sync->data.size());
      std::copy(c_.sync->data.begin(), c_.sync->data.end(), sync.data.begin());
      for (const auto* frames : {&layout_.inputFrames, &layout_.outputFrames})
        for (const FrameLayout& f : *frames)
          if (f.id == sync.id && f.extended == sync.extended)
            fail(c_.keyPath + ".sync.id", "the SYNC frame " +
                                              format::hexId(sync.id, sync.extended) +
                                              " is also an input or output frame");
      layout_.syncFrame = sync;
    }
  }

  const CanSection& c_;
  std::optional<DbcDatabase> dbc_;
  CanLayout layout_;
  /// Key paths of the signals of each frame (index 0: outputs, 1: inputs), for overlap messages.
  std::array<std::vector<std::vector<std::string>>, 2> keyPaths_;
};

}  // namespace

CanLayout resolveCanSection(const CanSection& section) {
  return Resolver(section).run();
}

CanLayout loadCanLayout(const nlohmann::json& section, const std::string& file,
                        const std::string& keyPath) {
  return resolveCanSection(parseCanSection(section, file, keyPath));
}

}  // namespace volcomp::config
