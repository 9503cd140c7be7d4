#include "volcomp/can/controller_node.hpp"

#include <algorithm>

#include "kernel_filter.hpp"

namespace volcomp::can {

using detail::filterFor;
using detail::index;

CanControllerNode::CanControllerNode(asio::io_context& io, CanLayout layout)
    : layout_(std::move(layout)), channel_(io, *this) {
  for (const FrameLayout& f : layout_.outputFrames) filters_.push_back(filterFor(f.id, f.extended));
  if (layout_.syncFrame)
    filters_.push_back(filterFor(layout_.syncFrame->id, layout_.syncFrame->extended));
  for (const FrameLayout& f : layout_.inputFrames) {
    Frame frame;
    frame.id = f.id;
    frame.extended = f.extended;
    frame.fd = layout_.fd;
    frame.length = static_cast<std::uint8_t>(validLengthAtLeast(f.length, layout_.fd));
    txFrames_.push_back(frame);
  }
  fresh_.assign(layout_.outputFrames.size(), false);
}

std::error_code CanControllerNode::open() noexcept {
  receiveFailed_ = false;
  std::fill(fresh_.begin(), fresh_.end(), false);
  const std::size_t kernelFilters = filters_.size() <= 32 ? filters_.size() : 0;
  return channel_.open(layout_.interfaceName, layout_.fd, {filters_.data(), kernelFilters}, 0);
}

void CanControllerNode::close() noexcept {
  channel_.close();
}

std::error_code CanControllerNode::publish(const loop::AxisSample& sample,
                                           std::uint64_t sequence) noexcept {
  for (std::size_t i = 0; i < txFrames_.size(); ++i) {
    Frame& frame = txFrames_[i];
    frame.data.fill(0);
    for (const FieldSignal& s : layout_.inputFrames[i].signals) {
      std::error_code ec;
      const auto payload = payloadOf(frame);
      switch (s.field) {
        case Field::PositionX:
        case Field::PositionY:
        case Field::PositionZ:
          ec = encode(s.spec, sample.positionMm[index(s.field) - index(Field::PositionX)], payload);
          break;
        case Field::AppliedX:
        case Field::AppliedY:
        case Field::AppliedZ:
          ec = encode(s.spec, sample.appliedOffsetMm[index(s.field) - index(Field::AppliedX)],
                      payload);
          break;
        case Field::Enable:
          ec = encode(s.spec, sample.enable ? 1.0 : 0.0, payload);
          break;
        case Field::Homed:
          ec = encode(s.spec, sample.homed ? 1.0 : 0.0, payload);
          break;
        case Field::Sequence: {
          const std::uint64_t mask =
              s.spec.length >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << s.spec.length) - 1;
          ec = encodeRaw(s.spec, sequence & mask, payload);
          break;
        }
        default:
          break;
      }
      if (ec) return ec;
    }
  }
  for (const Frame& frame : txFrames_)
    if (auto ec = channel_.send(frame, layout_.bitrateSwitch)) return ec;
  return {};
}

void CanControllerNode::onFrame(const Frame& frame) noexcept {
  if (layout_.syncFrame && frame.id == layout_.syncFrame->id &&
      frame.extended == layout_.syncFrame->extended) {
    ++syncs_;
    if (onSync_) onSync_();
    return;
  }
  for (std::size_t i = 0; i < layout_.outputFrames.size(); ++i) {
    const FrameLayout& layout = layout_.outputFrames[i];
    if (layout.id != frame.id || layout.extended != frame.extended) continue;
    if (frame.length < layout.length) {
      ++malformed_;
      return;
    }
    loop::OffsetCommand decoded = pending_;
    for (const FieldSignal& s : layout.signals) {
      std::error_code ec;
      std::uint64_t raw = 0;
      switch (s.field) {
        case Field::OffsetX:
        case Field::OffsetY:
        case Field::OffsetZ:
          ec = decode(s.spec, payloadOf(frame),
                      decoded.offsetMm[index(s.field) - index(Field::OffsetX)]);
          break;
        case Field::Status:
          ec = decodeRaw(s.spec, payloadOf(frame), raw);
          decoded.status = static_cast<std::uint16_t>(raw);
          break;
        case Field::Heartbeat:
          ec = decodeRaw(s.spec, payloadOf(frame), raw);
          decoded.heartbeat = static_cast<std::uint16_t>(raw);
          break;
        default:
          break;
      }
      if (ec) {
        ++malformed_;
        return;
      }
    }
    pending_ = decoded;
    fresh_[i] = true;
    if (std::all_of(fresh_.begin(), fresh_.end(), [](bool f) { return f; })) {
      std::fill(fresh_.begin(), fresh_.end(), false);
      last_ = pending_;
      ++commands_;
      if (onCommand_) onCommand_(last_);
    }
    return;
  }
}

}  // namespace volcomp::can
