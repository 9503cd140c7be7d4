#include "volcomp/modbus/error.hpp"

#include <string>

namespace volcomp::modbus {
namespace {

class ModbusCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "modbus"; }

  std::string message(int ev) const override {
    switch (static_cast<Errc>(ev)) {
      case Errc::illegal_function:
        return "Modbus exception 1: illegal function";
      case Errc::illegal_data_address:
        return "Modbus exception 2: illegal data address";
      case Errc::illegal_data_value:
        return "Modbus exception 3: illegal data value";
      case Errc::server_device_failure:
        return "Modbus exception 4: server device failure";
      case Errc::acknowledge:
        return "Modbus exception 5: acknowledge";
      case Errc::server_device_busy:
        return "Modbus exception 6: server device busy";
      case Errc::negative_acknowledge:
        return "Modbus exception 7: negative acknowledge";
      case Errc::memory_parity_error:
        return "Modbus exception 8: memory parity error";
      case Errc::gateway_path_unavailable:
        return "Modbus exception 10: gateway path unavailable";
      case Errc::gateway_target_failed:
        return "Modbus exception 11: gateway target failed to respond";
      case Errc::response_timeout:
        return "no response within the response timeout";
      case Errc::bad_crc:
        return "response with a bad CRC";
      case Errc::bad_data:
        return "response does not match the request";
      case Errc::bad_exception:
        return "malformed exception response";
      case Errc::unknown_exception:
        return "unknown Modbus exception code";
      case Errc::too_much_data:
        return "response longer than expected";
      case Errc::bad_slave:
        return "response from another slave id";
      case Errc::value_not_finite:
        return "register value is not a finite number";
      case Errc::value_out_of_range:
        return "value does not fit its register type";
      case Errc::no_master_write:
        return "the master has not written a complete position set yet";
    }
    return "unknown Modbus error " + std::to_string(ev);
  }

  std::error_condition default_error_condition(int ev) const noexcept override {
    if (static_cast<Errc>(ev) == Errc::response_timeout) {
      return std::make_error_condition(std::errc::timed_out);
    }
    return {ev, *this};
  }
};

}  // namespace

const std::error_category& modbusCategory() noexcept {
  static const ModbusCategory category;
  return category;
}

}  // namespace volcomp::modbus
