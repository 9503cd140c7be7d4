#pragma once
// What every fuzz target checks besides "no crash, no sanitizer report": a parser refuses bad
// input with its documented exception (config::ConfigError, model::ModelError) whose message is
// fit to print, meaning valid UTF-8 without control characters or terminal escapes, and bounded.
// Any other exception escapes LLVMFuzzerTestOneInput and ends the run (libFuzzer reports it as a
// crash): an input must never reach the user as "internal error".

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string_view>

#include "volcomp/config/printable.hpp"

namespace volcomp::fuzz {

/// Longest message a refusal may have (the longest expected-list of a key is far shorter).
inline constexpr std::size_t kMaxMessageBytes = 4096;

[[noreturn]] inline void finding(const char* what, std::string_view detail) {
  std::fprintf(stderr, "FUZZ FINDING: %s: %.*s\n", what, static_cast<int>(detail.size()),
               detail.data());
  std::abort();
}

/// Aborts when a refusal's message could not be shown as it is.
inline void checkMessage(const std::exception& e) {
  const std::string_view message = e.what();
  if (message.empty()) finding("empty error message", message);
  if (message.size() > kMaxMessageBytes) finding("error message too long", message.substr(0, 200));
  if (!config::isPrintable(message)) finding("error message not printable", message);
}

/// Aborts when a condition that must hold for every input does not.
inline void require(bool condition, const char* what) {
  if (!condition) finding("broken invariant", what);
}

/// Reads typed values off the front of the fuzz input; past its end every value is zero, so any
/// input is a complete one.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <typename T>
  T take() {
    T value{};
    const std::size_t n = std::min(sizeof(T), size_ - pos_);
    std::memcpy(&value, data_ + pos_, n);
    pos_ += n;
    return value;
  }
  std::size_t remaining() const { return size_ - pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// The fuzz input as text.
inline std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace volcomp::fuzz
