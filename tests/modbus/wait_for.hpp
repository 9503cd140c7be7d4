#pragma once
// Waiting on a condition with a deadline (never a bare sleep for synchronisation): the condition
// is re-checked every millisecond until it holds or the timeout expires.

#include <chrono>
#include <thread>

namespace volcomp::test {

template <typename Predicate>
bool waitFor(Predicate&& condition, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace volcomp::test
