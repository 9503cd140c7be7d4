#include "volcomp/loop/status.hpp"

namespace volcomp::loop {

std::string_view faultName(FaultCode code) noexcept {
  switch (code) {
    case FaultCode::None:
      return "none";
    case FaultCode::StaleInput:
      return "stale-input";
    case FaultCode::OutOfTravel:
      return "out-of-travel";
    case FaultCode::InvalidInput:
      return "invalid-input";
    case FaultCode::ModelInvalid:
      return "model-invalid";
    case FaultCode::NotConverged:
      return "not-converged";
    case FaultCode::TransactionError:
      return "transaction-error";
    case FaultCode::SustainedLimit:
      return "sustained-limit";
    case FaultCode::ReadbackOutOfRange:
      return "readback-out-of-range";
  }
  return "unknown";
}

}  // namespace volcomp::loop
