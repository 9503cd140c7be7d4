#include "volcomp/config/config_error.hpp"

#include <utility>

#include "volcomp/config/printable.hpp"

namespace volcomp::config {
namespace {

std::string composeWhat(const std::string& file, const std::string& keyPath,
                        const std::string& message) {
  constexpr std::size_t kPartBytes = 512;
  constexpr std::size_t kMessageBytes = 2048;
  std::string what = file.empty() ? std::string("<input>") : printable(file, kPartBytes);
  what += ": ";
  if (!keyPath.empty()) {
    what += printable(keyPath, kPartBytes);
    what += ": ";
  }
  what += printable(message, kMessageBytes);
  return what;
}

}  // namespace

ConfigError::ConfigError(std::string file, std::string keyPath, std::string message)
    : std::runtime_error(composeWhat(file, keyPath, message)),
      file_(std::move(file)),
      keyPath_(std::move(keyPath)),
      message_(std::move(message)) {}

}  // namespace volcomp::config
