#pragma once
/// The smallest of the last N durations pushed (a sliding window over a fixed ring): the least
/// transport delay of recent transactions, for the controller clock's offset and the limiter's
/// round trip. noexcept and allocation-free.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>

namespace volcomp::loop {

template <std::size_t N>
class WindowMinimum {
 public:
  /// Adds `value`; the oldest falls out once N are held. O(1), except for a scan of the N held
  /// when the one that fell out was the smallest.
  void push(std::chrono::nanoseconds value) noexcept {
    const bool full = count_ == N;
    const std::chrono::nanoseconds evicted = values_[next_];
    values_[next_] = value;
    next_ = (next_ + 1) % N;
    count_ = std::min(count_ + 1, N);
    if (count_ == 1 || value <= min_) {
      min_ = value;
    } else if (full && evicted == min_) {
      min_ = *std::min_element(values_.begin(), values_.end());
    }
  }

  /// Forgets every value (min() is 0 until the next push).
  void reset() noexcept {
    count_ = 0;
    next_ = 0;
    min_ = std::chrono::nanoseconds(0);
  }

  /// The smallest value held, 0 when none is.
  std::chrono::nanoseconds min() const noexcept { return min_; }
  std::size_t size() const noexcept { return count_; }

 private:
  std::array<std::chrono::nanoseconds, N> values_{};
  std::size_t count_ = 0;
  std::size_t next_ = 0;
  std::chrono::nanoseconds min_{0};
};

}  // namespace volcomp::loop
