#pragma once
/// A CAN frame as the codec sees it: identifier, format and payload. Independent of SocketCAN so
/// that the codec stays pure (the driver converts to/from struct can_frame / canfd_frame).

#include <array>
#include <cstddef>
#include <cstdint>

namespace volcomp::can {

inline constexpr std::size_t kClassicMaxLength = 8;           ///< classical CAN payload, bytes
inline constexpr std::size_t kFdMaxLength = 64;               ///< CAN FD payload, bytes
inline constexpr std::uint32_t kStandardIdMax = 0x7FFu;       ///< 11-bit identifier
inline constexpr std::uint32_t kExtendedIdMax = 0x1FFFFFFFu;  ///< 29-bit identifier

struct Frame {
  std::uint32_t id = 0;     ///< 11-bit (standard) or 29-bit (extended) identifier, no flags
  bool extended = false;    ///< 29-bit identifier
  bool fd = false;          ///< CAN FD frame (payload up to 64 bytes)
  std::uint8_t length = 0;  ///< payload length in bytes (a valid DLC length for `fd`)
  std::array<std::uint8_t, kFdMaxLength> data{};
  bool operator==(const Frame&) const = default;
};

/// True when `id` fits the identifier format (11 or 29 bits).
constexpr bool isValidId(std::uint32_t id, bool extended) noexcept {
  return id <= (extended ? kExtendedIdMax : kStandardIdMax);
}

/// True for the payload lengths a DLC can express: 0..8 for classical CAN; 0..8, 12, 16, 20, 24,
/// 32, 48, 64 for CAN FD.
constexpr bool isValidLength(std::size_t length, bool fd) noexcept {
  if (length <= kClassicMaxLength) return true;
  if (!fd) return false;
  return length == 12 || length == 16 || length == 20 || length == 24 || length == 32 ||
         length == 48 || length == 64;
}

/// The smallest valid payload length >= `length`, or 0 when none exists (longer than 8 bytes for
/// classical CAN, longer than 64 bytes for CAN FD). A request of 0 gives 0.
constexpr std::size_t validLengthAtLeast(std::size_t length, bool fd) noexcept {
  constexpr std::array<std::size_t, 7> kFdSteps{12, 16, 20, 24, 32, 48, 64};
  if (length <= kClassicMaxLength) return length;
  if (!fd) return 0;
  for (std::size_t step : kFdSteps)
    if (length <= step) return step;
  return 0;
}

}  // namespace volcomp::can
