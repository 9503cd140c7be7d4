#include "volcomp/can/errors.hpp"

#include <string>

namespace volcomp::can {
namespace {

class CanCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "volcomp.can"; }
  std::string message(int value) const override {
    switch (static_cast<Errc>(value)) {
      case Errc::OutOfRange:
        return "value out of the signal's range";
      case Errc::NotFinite:
        return "value is NaN or infinite";
      case Errc::OutsideFrame:
        return "signal lies outside the frame payload";
      case Errc::StaleInput:
        return "no complete set of input frames within the stale timeout";
      case Errc::NoResponse:
        return "no response to the SYNC frame within the response timeout";
      case Errc::BusOff:
        return "CAN controller is bus-off";
      case Errc::ErrorPassive:
        return "CAN controller is error-passive";
      case Errc::TxDropped:
        return "transmit queue full, frame dropped";
    }
    return "unknown CAN error";
  }
};

}  // namespace

const std::error_category& canCategory() noexcept {
  static const CanCategory category;
  return category;
}

std::error_code make_error_code(Errc e) noexcept {
  return {static_cast<int>(e), canCategory()};
}

}  // namespace volcomp::can
