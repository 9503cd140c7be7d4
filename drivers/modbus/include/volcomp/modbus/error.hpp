#pragma once
/// std::error_code category for Modbus: the exception codes a server answers with (values 1..11
/// as on the wire) and the protocol failures libmodbus reports (timeouts, CRC, malformed
/// responses), plus codec failures. Link loss is reported with generic std::errc values (see
/// volcomp/loop/ports.hpp), never with this category.

#include <system_error>

namespace volcomp::modbus {

enum class Errc {
  // Modbus exception codes (Modbus Application Protocol v1.1b3, section 7).
  illegal_function = 1,
  illegal_data_address = 2,
  illegal_data_value = 3,
  server_device_failure = 4,
  acknowledge = 5,
  server_device_busy = 6,
  negative_acknowledge = 7,
  memory_parity_error = 8,
  gateway_path_unavailable = 10,
  gateway_target_failed = 11,
  // Failed transactions on a live link.
  response_timeout = 100,  ///< no (complete) response within the response timeout
  bad_crc,                 ///< RTU frame with a wrong CRC
  bad_data,                ///< response does not match the request
  bad_exception,           ///< malformed exception response
  unknown_exception,       ///< exception code outside 1..11
  too_much_data,           ///< response longer than expected
  bad_slave,               ///< response from another slave id
  // Codec.
  value_not_finite,    ///< a float input register held NaN or infinity, or an output was NaN
  value_out_of_range,  ///< an output does not fit its register type (nothing was written)
  // Server role.
  no_master_write,  ///< the master has not yet written a complete position set
};

const std::error_category& modbusCategory() noexcept;

inline std::error_code make_error_code(Errc e) noexcept {
  return {static_cast<int>(e), modbusCategory()};
}

}  // namespace volcomp::modbus

template <>
struct std::is_error_code_enum<volcomp::modbus::Errc> : std::true_type {};
