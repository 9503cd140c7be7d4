#include "libmodbus_errno.hpp"

#include <cerrno>

#include <modbus/modbus.h>

#include "volcomp/modbus/error.hpp"

namespace volcomp::modbus {

std::error_code fromLibmodbusErrno(int err) noexcept {
  if (err > MODBUS_ENOBASE && err <= EMBXGTAR) {
    return {err - MODBUS_ENOBASE, modbusCategory()};
  }
  switch (err) {
    case ETIMEDOUT:
      return Errc::response_timeout;
    case EMBBADCRC:
      return Errc::bad_crc;
    case EMBBADDATA:
      return Errc::bad_data;
    case EMBBADEXC:
      return Errc::bad_exception;
    case EMBUNKEXC:
      return Errc::unknown_exception;
    case EMBMDATA:
      return Errc::too_much_data;
    case EMBBADSLAVE:
      return Errc::bad_slave;
    default:
      return {err, std::generic_category()};
  }
}

}  // namespace volcomp::modbus
