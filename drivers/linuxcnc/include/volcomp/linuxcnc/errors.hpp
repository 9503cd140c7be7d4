#pragma once
/// std::error_code category of the LinuxCNC adapter: why joining LinuxCNC's HAL failed. A missing
/// HAL (LinuxCNC not running) is std::errc::connection_refused and a HAL of another user
/// std::errc::permission_denied; the adapter's notices name the pin or signal concerned.

#include <system_error>

namespace volcomp::linuxcnc {

enum class HalErrc {
  hal_call_failed = 1,  ///< hal_init, hal_pin_new, hal_malloc or hal_ready refused
  component_in_use,     ///< a running volcompd already owns the HAL component
  missing_signal,       ///< a required HAL signal is not declared
  link_failed,          ///< a pin could not join its signal (wrong type, another writer)
};

const std::error_category& halCategory() noexcept;

inline std::error_code make_error_code(HalErrc e) noexcept {
  return {static_cast<int>(e), halCategory()};
}

}  // namespace volcomp::linuxcnc

template <>
struct std::is_error_code_enum<volcomp::linuxcnc::HalErrc> : std::true_type {};
