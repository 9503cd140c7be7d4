#pragma once
// Waiting on a condition with a deadline, for tests: the one polling helper of the test suites.

#include <chrono>
#include <thread>

namespace volcomp::testutil {

/// Polls `condition` every 2 ms until it holds or `timeout` expires; returns whether it held.
/// For conditions that have no file descriptor to wait on (a file's content, a process state, a
/// transaction that succeeds again).
template <typename Predicate>
bool waitUntil(Predicate&& condition, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

}  // namespace volcomp::testutil
