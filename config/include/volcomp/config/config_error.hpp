#pragma once
/// Typed configuration errors: every rejection names the file, the key path and what was expected.

#include <stdexcept>
#include <string>

namespace volcomp::config {

class ConfigError : public std::runtime_error {
 public:
  /// what() reads "FILE: KEY.PATH: MESSAGE" (the key part omitted when empty), each part passed
  /// through printable() (volcomp/config/printable.hpp) and bounded (file and key path 512 bytes,
  /// message 2048), since all three may hold pieces of the input. The accessors return the parts
  /// as given.
  ConfigError(std::string file, std::string keyPath, std::string message);
  const std::string& file() const noexcept { return file_; }
  const std::string& keyPath() const noexcept { return keyPath_; }
  const std::string& message() const noexcept { return message_; }

 private:
  std::string file_, keyPath_, message_;
};

}  // namespace volcomp::config
