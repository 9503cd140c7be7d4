#include "volcomp/modbus/server_bank.hpp"

#include <algorithm>

namespace volcomp::modbus {
namespace {

std::uint16_t word(const std::uint8_t* p) noexcept {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

bool overlaps(Block a, Block b) noexcept {
  return a.count > 0 && b.count > 0 && a.start < b.start + b.count && b.start < a.start + a.count;
}

bool inside(Block outer, Block inner) noexcept {
  return outer.contains(inner.start, inner.count);
}

}  // namespace

ServerLayout layoutServerBank(const RegisterMap& map) noexcept {
  const RegisterPlan plan = planRegisters(map);
  ServerLayout layout;
  layout.masterWrite = plan.holdingRead;
  layout.output = plan.write;
  int lo = plan.write.start;
  int hi = plan.write.start + plan.write.count;
  if (plan.holdingRead.count > 0) {
    lo = std::min<int>(lo, plan.holdingRead.start);
    hi = std::max<int>(hi, plan.holdingRead.start + plan.holdingRead.count);
  }
  layout.bank = {static_cast<std::uint16_t>(lo), static_cast<std::uint16_t>(hi - lo)};
  return layout;
}

std::optional<ServerRequest> parseServerRequest(std::span<const std::uint8_t> pdu) noexcept {
  if (pdu.empty()) return std::nullopt;
  ServerRequest r;
  r.function = pdu[0];
  const std::uint8_t* p = pdu.data();
  const auto need = [&](std::size_t n) noexcept { return pdu.size() >= n; };
  switch (r.function) {
    case 0x03:  // read holding registers
      if (!need(5)) return std::nullopt;
      r.read = {word(p + 1), word(p + 3)};
      break;
    case 0x06:  // write single register
    case 0x16:  // mask write register
      if (!need(5)) return std::nullopt;
      r.write = {word(p + 1), 1};
      break;
    case 0x10:  // write multiple registers
      if (!need(5)) return std::nullopt;
      r.write = {word(p + 1), word(p + 3)};
      break;
    case 0x17:  // read/write multiple registers
      if (!need(9)) return std::nullopt;
      r.read = {word(p + 1), word(p + 3)};
      r.write = {word(p + 5), word(p + 7)};
      break;
    default:
      break;
  }
  return r;
}

std::uint8_t refuseRequest(const ServerLayout& layout, std::span<const std::uint8_t> pdu) noexcept {
  if (pdu.empty()) return kIllegalFunction;
  const std::uint8_t* p = pdu.data();
  const std::size_t size = pdu.size();
  // Quantity limits are the protocol's: what one request or its reply can carry.
  const auto quantity = [](std::uint16_t n, std::uint16_t most) noexcept {
    return n >= 1 && n <= most;
  };
  Block read;
  Block write;
  switch (p[0]) {
    case 0x03:
      if (size != 5 || !quantity(word(p + 3), 125)) return kIllegalDataValue;
      read = {word(p + 1), word(p + 3)};
      break;
    case 0x06:
      if (size != 5) return kIllegalDataValue;
      write = {word(p + 1), 1};
      break;
    case 0x16:
      if (size != 7) return kIllegalDataValue;
      write = {word(p + 1), 1};
      break;
    case 0x10:
      if (size < 6 || !quantity(word(p + 3), 123) || p[5] != 2 * word(p + 3) || size != 6U + p[5]) {
        return kIllegalDataValue;
      }
      write = {word(p + 1), word(p + 3)};
      break;
    case 0x17:
      if (size < 10 || !quantity(word(p + 3), 125) || !quantity(word(p + 7), 121) ||
          p[9] != 2 * word(p + 7) || size != 10U + p[9]) {
        return kIllegalDataValue;
      }
      read = {word(p + 1), word(p + 3)};
      write = {word(p + 5), word(p + 7)};
      break;
    default:
      return kIllegalFunction;
  }
  if (read.count > 0 && !inside(layout.bank, read)) return kIllegalDataAddress;
  if (write.count > 0 && (!inside(layout.masterWrite, write) || overlaps(layout.output, write))) {
    return kIllegalDataAddress;
  }
  return 0;
}

PositionWriteTracker::PositionWriteTracker(const RegisterMap& map) noexcept {
  for (const ValueRegister& p : map.position) {
    const int width = registerWidth(p.format.type);
    for (int i = 0; i < width && count_ < static_cast<int>(addresses_.size()); ++i) {
      addresses_[static_cast<std::size_t>(count_++)] = static_cast<std::uint16_t>(p.address + i);
    }
  }
  all_ = static_cast<std::uint16_t>((1u << count_) - 1u);
}

bool PositionWriteTracker::onWrite(Block write) noexcept {
  for (int i = 0; i < count_; ++i) {
    if (write.contains(addresses_[static_cast<std::size_t>(i)], 1)) {
      written_ = static_cast<std::uint16_t>(written_ | (1u << i));
    }
  }
  if (count_ == 0 || written_ != all_) return false;
  written_ = 0;
  return true;
}

bool clientAllowed(std::uint32_t address, std::span<const std::uint32_t> allowed) noexcept {
  return allowed.empty() || std::find(allowed.begin(), allowed.end(), address) != allowed.end();
}

}  // namespace volcomp::modbus
