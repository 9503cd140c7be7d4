#pragma once
// libmodbus reports failures through errno: its own codes above MODBUS_ENOBASE (exception
// replies, CRC, malformed responses) and plain errno values.

#include <system_error>

namespace volcomp::modbus {

/// Maps an errno value set by libmodbus: Modbus exceptions and protocol errors to
/// modbusCategory(), ETIMEDOUT to Errc::response_timeout, anything else to
/// std::generic_category.
std::error_code fromLibmodbusErrno(int err) noexcept;

}  // namespace volcomp::modbus
