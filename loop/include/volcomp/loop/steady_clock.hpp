#pragma once
/// The production Clock: std::chrono::steady_clock.

#include "volcomp/loop/ports.hpp"

namespace volcomp::loop {

class SteadyClock final : public Clock {
 public:
  time_point now() const noexcept override { return std::chrono::steady_clock::now(); }
};

}  // namespace volcomp::loop
