#include "volcomp/can/controller_port.hpp"

#include <linux/can/error.h>

#include "kernel_filter.hpp"
#include "volcomp/can/errors.hpp"

namespace volcomp::can {
namespace {

using Clock = std::chrono::steady_clock;

constexpr can_err_mask_t kErrorClasses = CAN_ERR_CRTL | CAN_ERR_BUSOFF | CAN_ERR_RESTARTED;
constexpr std::size_t kMaxKernelFilters = 32;

constexpr std::uint64_t lowMask(unsigned bits) noexcept {
  return bits >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << bits) - 1;
}

}  // namespace

using detail::filterFor;
using detail::index;

CanControllerPort::CanControllerPort(CanLayout layout)
    : layout_(std::move(layout)), channel_(io_, *this) {
  slots_.resize(layout_.inputFrames.size());
  latestFrames_.resize(layout_.inputFrames.size());
  for (std::size_t i = 0; i < layout_.inputFrames.size(); ++i) {
    const FrameLayout& f = layout_.inputFrames[i];
    if (layout_.inputFrames.size() <= kMaxKernelFilters)
      filters_.push_back(filterFor(f.id, f.extended));
    for (const FieldSignal& s : f.signals) fieldSlot_[index(s.field)] = i;
  }
  for (const FrameLayout& f : layout_.outputFrames) {
    Frame frame;
    frame.id = f.id;
    frame.extended = f.extended;
    frame.fd = layout_.fd;
    frame.length = static_cast<std::uint8_t>(f.length);
    txFrames_.push_back(frame);
  }
  latest_.hasAppliedOffsets = layout_.hasAppliedOffsets;
  latest_.hasSequence = layout_.hasSequence;
}

CanControllerPort::~CanControllerPort() {
  channel_.close();
}

std::error_code CanControllerPort::connect() noexcept {
  channel_.close();
  // Drop the cancelled receive so that nothing from the old socket reaches the new state.
  io_.restart();
  io_.poll();
  for (InputSlot& slot : slots_) slot.fresh = false;
  haveSet_ = false;
  linkLost_ = false;
  busState_ = BusState::ErrorActive;
  socketDrops_ = 0;
  dropsAfterDrain_ = stats_.receiveQueueDrops;
  if (auto ec = channel_.open(layout_.interfaceName, layout_.fd, filters_, kErrorClasses))
    return ec;
  connectTime_ = Clock::now();
  return {};
}

void CanControllerPort::disconnect() noexcept {
  channel_.close();
  io_.restart();
  io_.poll();
}

bool CanControllerPort::connected() const noexcept {
  return channel_.isOpen() && !linkLost_;
}

void CanControllerPort::countDrops() noexcept {
  const std::uint32_t drops = channel_.droppedFrames();
  // The kernel's counter is 32 bits: the difference is right across its wrap.
  stats_.receiveQueueDrops += static_cast<std::uint32_t>(drops - socketDrops_);
  socketDrops_ = drops;
}

void CanControllerPort::drained() noexcept {
  countDrops();
  dropsAfterDrain_ = stats_.receiveQueueDrops;
}

void CanControllerPort::pump() noexcept {
  if (io_.stopped()) io_.restart();
  io_.poll();
  drained();
}

std::error_code CanControllerPort::linkDown() noexcept {
  channel_.close();
  return std::make_error_code(std::errc::network_down);
}

std::error_code CanControllerPort::busError() noexcept {
  const Clock::time_point now = Clock::now();
  const bool quiet = now - lastStateReport_ >= layout_.staleTimeout;
  if (busState_ == BusState::BusOff && quiet && channel_.carrierUp()) {
    busState_ = BusState::ErrorActive;
    ++stats_.busOffEndedByCarrier;
  }
  if (busState_ == BusState::ErrorPassive && quiet) {
    // The kernel reports the way back to error-active once, and a full receive queue may have
    // dropped that report. Only then (frames were dropped after the passive report) do complete
    // input sets since the report, fresh now, end the state: the controller is talking again.
    // Without drops the report cannot have been lost, and a controller that stays passive keeps
    // the fault however well the frames flow.
    countDrops();
    if (stats_.receiveQueueDrops != dropsAtStateReport_ && haveSet_ &&
        setTime_ > lastStateReport_ && now - setTime_ <= layout_.staleTimeout) {
      busState_ = BusState::ErrorActive;
      ++stats_.errorPassiveEndedAfterDrops;
    }
  }
  if (busState_ == BusState::BusOff) return Errc::BusOff;
  if (busState_ == BusState::ErrorPassive) return Errc::ErrorPassive;
  return {};
}

std::error_code CanControllerPort::waitForSet(Clock::time_point deadline) noexcept {
  const std::uint64_t before = stats_.completeSets;
  while (stats_.completeSets == before && !linkLost_ && channel_.isOpen() &&
         Clock::now() < deadline) {
    if (io_.stopped()) io_.restart();
    io_.run_one_until(deadline);
  }
  drained();
  if (linkLost_) return linkDown();
  return stats_.completeSets != before ? std::error_code{} : std::error_code{Errc::NoResponse};
}

std::error_code CanControllerPort::read(loop::AxisSample& out) noexcept {
  if (!channel_.isOpen()) return std::make_error_code(std::errc::not_connected);
  pump();
  if (linkLost_) return linkDown();
  // Error-passive still sends: with the sync trigger the SYNC goes out, and its answer shows
  // whether the controller talks again (see busError); broadcasts show it without asking.
  if (auto ec = busError(); ec == Errc::BusOff || (ec && layout_.trigger != Trigger::Sync))
    return ec;

  if (layout_.trigger == Trigger::Sync) {
    // Frames that arrived before this SYNC belong to an earlier cycle.
    for (InputSlot& slot : slots_) slot.fresh = false;
    if (auto ec = channel_.send(*layout_.syncFrame, layout_.bitrateSwitch)) {
      if (ec == std::errc::network_down) {
        ++stats_.linkErrors;
        lastLinkError_ = ec;
        linkLost_ = true;
        return linkDown();
      }
      if (ec == Errc::TxDropped) ++stats_.txDropped;
      return ec;
    }
    ++stats_.framesSent;
    if (auto ec = waitForSet(Clock::now() + layout_.responseTimeout)) return ec;
    if (auto ec = busError()) return ec;
    out = latest_;
    return {};
  }

  Clock::time_point now = Clock::now();
  if (!haveSet_ && now < connectTime_ + layout_.staleTimeout) {
    const std::error_code ec = waitForSet(connectTime_ + layout_.staleTimeout);
    if (ec == std::errc::network_down) return ec;
    now = Clock::now();
  }
  if (auto ec = busError()) return ec;
  if (!haveSet_ || now - setTime_ > layout_.staleTimeout) return Errc::StaleInput;
  out = latest_;
  return {};
}

std::error_code CanControllerPort::write(const loop::OffsetCommand& command) noexcept {
  if (!channel_.isOpen()) return std::make_error_code(std::errc::not_connected);
  pump();
  if (linkLost_) return linkDown();
  if (busError() == Errc::BusOff) return Errc::BusOff;

  for (std::size_t i = 0; i < txFrames_.size(); ++i) {
    Frame& frame = txFrames_[i];
    frame.data.fill(0);
    for (const FieldSignal& s : layout_.outputFrames[i].signals) {
      std::error_code ec;
      switch (s.field) {
        case Field::OffsetX:
        case Field::OffsetY:
        case Field::OffsetZ:
          ec = encode(s.spec, command.offsetMm[index(s.field) - index(Field::OffsetX)],
                      payloadOf(frame));
          break;
        case Field::Status:
          ec = encodeRaw(s.spec, command.status, payloadOf(frame));
          break;
        case Field::Heartbeat:
          // A counter: it wraps modulo 2^length by design.
          ec = encodeRaw(s.spec, command.heartbeat & lowMask(s.spec.length), payloadOf(frame));
          break;
        default:
          break;
      }
      if (ec) return ec;
    }
  }
  std::error_code result;
  for (const Frame& frame : txFrames_) {
    const std::error_code ec = channel_.send(frame, layout_.bitrateSwitch);
    if (!ec) {
      ++stats_.framesSent;
    } else if (ec == Errc::TxDropped) {
      ++stats_.txDropped;
      result = ec;
    } else if (ec == std::errc::network_down) {
      ++stats_.linkErrors;
      lastLinkError_ = ec;
      linkLost_ = true;
      return linkDown();
    } else {
      return ec;
    }
  }
  return result;
}

void CanControllerPort::receive(const canfd_frame& datagram, std::size_t bytes) noexcept {
  deliverDatagram(datagram, bytes, layout_.fd, *this);
}

void CanControllerPort::onFrame(const Frame& frame) noexcept {
  std::size_t slotIndex = 0;
  while (slotIndex < slots_.size() && (layout_.inputFrames[slotIndex].id != frame.id ||
                                       layout_.inputFrames[slotIndex].extended != frame.extended))
    ++slotIndex;
  if (slotIndex == slots_.size()) {
    ++stats_.unknownFrames;
    return;
  }
  const FrameLayout& layout = layout_.inputFrames[slotIndex];
  if (frame.length < layout.length) {
    ++stats_.malformedFrames;
    return;
  }
  // Decode into a scratch copy so that a bad frame leaves the slot as it was.
  std::array<double, kFieldCount> values = slots_[slotIndex].values;
  std::uint64_t sequence = 0;
  for (const FieldSignal& s : layout.signals) {
    std::error_code ec;
    if (s.field == Field::Sequence)
      ec = decodeRaw(s.spec, payloadOf(frame), sequence);
    else
      ec = decode(s.spec, payloadOf(frame), values[index(s.field)]);
    if (ec) {
      ++stats_.malformedFrames;
      return;
    }
  }
  InputSlot& slot = slots_[slotIndex];
  if (slot.fresh) ++stats_.discardedFrames;
  slot.values = values;
  slot.frame = frame;
  slot.sequence = sequence;
  slot.fresh = true;
  ++stats_.framesReceived;
  completeIfConsistent(slotIndex);
}

void CanControllerPort::completeIfConsistent(std::size_t newest) noexcept {
  if (layout_.hasSequence) {
    // The newest frame defines the current set: frames of other sets are superseded.
    const std::uint64_t current = slots_[newest].sequence;
    for (InputSlot& slot : slots_) {
      if (slot.fresh && slot.sequence != current) {
        slot.fresh = false;
        ++stats_.discardedFrames;
      }
    }
  }
  for (const InputSlot& slot : slots_)
    if (!slot.fresh) return;

  auto value = [&](Field f) { return slots_[fieldSlot_[index(f)]].values[index(f)]; };
  for (std::size_t axis = 0; axis < 3; ++axis) {
    latest_.positionMm[axis] = value(static_cast<Field>(index(Field::PositionX) + axis));
    if (layout_.hasAppliedOffsets)
      latest_.appliedOffsetMm[axis] = value(static_cast<Field>(index(Field::AppliedX) + axis));
  }
  latest_.enable = value(Field::Enable) != 0.0;
  latest_.homed = value(Field::Homed) != 0.0;
  if (layout_.hasSequence)
    latest_.sequence = static_cast<std::uint16_t>(slots_[newest].sequence & 0xFFFFu);
  for (std::size_t i = 0; i < slots_.size(); ++i) {
    latestFrames_[i] = slots_[i].frame;
    slots_[i].fresh = false;
  }
  haveSet_ = true;
  setTime_ = Clock::now();
  ++stats_.completeSets;
}

void CanControllerPort::onErrorFrame(std::uint32_t errorClass, const Frame& frame) noexcept {
  ++stats_.errorFrames;
  if ((errorClass & CAN_ERR_BUSOFF) != 0) {
    if (busState_ != BusState::BusOff) ++stats_.busOffEvents;
    busState_ = BusState::BusOff;
    noteStateReport();
    return;
  }
  if ((errorClass & CAN_ERR_RESTARTED) != 0) busState_ = BusState::ErrorActive;
  if ((errorClass & CAN_ERR_CRTL) != 0 && frame.length > 1) {
    const std::uint8_t state = frame.data[1];
    if ((state & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0) {
      if (busState_ != BusState::ErrorPassive) ++stats_.errorPassiveEvents;
      busState_ = BusState::ErrorPassive;
      noteStateReport();
    } else if ((state & CAN_ERR_CRTL_ACTIVE) != 0) {
      busState_ = BusState::ErrorActive;
    } else if ((state & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0) {
      // Warning is below passive: a controller coming down from passive reports it.
      busState_ = BusState::ErrorWarning;
    }
  }
}

void CanControllerPort::noteStateReport() noexcept {
  lastStateReport_ = Clock::now();
  // The queue was empty when the last drain ended: drops counted since then may have come after
  // this report, those before cannot have.
  dropsAtStateReport_ = dropsAfterDrain_;
}

void CanControllerPort::onMalformed() noexcept {
  ++stats_.malformedFrames;
}

void CanControllerPort::onReceiveError(std::error_code ec) noexcept {
  // Any receive failure leaves the socket unusable: treat it as a lost link and reopen.
  ++stats_.linkErrors;
  lastLinkError_ = ec;
  linkLost_ = true;
}

}  // namespace volcomp::can
