#pragma once
/// SocketCAN receive filters for the frames a port or node listens to.

#include <linux/can.h>

#include <cstddef>
#include <cstdint>

#include "volcomp/can/layout.hpp"

namespace volcomp::can::detail {

/// The kernel filter that passes exactly the data frames with identifier `id` in the given
/// format. Matching the EFF and RTR flags too keeps remote requests and the other identifier
/// format out.
inline can_filter filterFor(std::uint32_t id, bool extended) noexcept {
  return extended ? can_filter{(id & CAN_EFF_MASK) | CAN_EFF_FLAG,
                               CAN_EFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG}
                  : can_filter{id & CAN_SFF_MASK, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
}

/// A field's position in per-field arrays.
constexpr std::size_t index(Field f) noexcept {
  return static_cast<std::size_t>(f);
}

}  // namespace volcomp::can::detail
