#include "volcomp/config/config_error.hpp"

#include <utility>

namespace volcomp::config {
namespace {

std::string composeWhat(const std::string& file, const std::string& keyPath,
                        const std::string& message) {
  std::string what = file.empty() ? std::string("<input>") : file;
  what += ": ";
  if (!keyPath.empty()) {
    what += keyPath;
    what += ": ";
  }
  what += message;
  return what;
}

}  // namespace

ConfigError::ConfigError(std::string file, std::string keyPath, std::string message)
    : std::runtime_error(composeWhat(file, keyPath, message)),
      file_(std::move(file)),
      keyPath_(std::move(keyPath)),
      message_(std::move(message)) {}

}  // namespace volcomp::config
