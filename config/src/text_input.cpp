#include "volcomp/config/text_input.hpp"

#include <cerrno>
#include <filesystem>
#include <system_error>

#include "volcomp/config/config_error.hpp"

namespace volcomp::config {
namespace {

std::string sizeText(std::size_t bytes) {
  if (bytes >= (std::size_t{1} << 20) && bytes % (std::size_t{1} << 20) == 0) {
    return std::to_string(bytes >> 20) + " MiB";
  }
  if (bytes >= 1024 && bytes % 1024 == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

// An ifstream opens a directory without complaint on Linux and then reads nothing, which a
// parser would report as an empty or invalid file.
void refuseDirectory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw ConfigError(path, "", "is a directory, not a file");
  }
}

}  // namespace

std::ifstream openTextFile(const std::string& path) {
  refuseDirectory(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const std::error_code ec(errno, std::generic_category());
    throw ConfigError(path, "", "cannot open file: " + ec.message());
  }
  return in;
}

std::string readTextFile(const std::string& path, std::size_t maxBytes) {
  std::ifstream in = openTextFile(path);
  std::string text;
  // Read in pieces up to the limit rather than trusting a size from stat(): pipes, FIFOs and
  // /proc files report none, and a file may grow while it is read.
  constexpr std::size_t kChunk = 1 << 16;
  while (true) {
    const std::size_t old = text.size();
    text.resize(old + kChunk);
    in.read(text.data() + old, static_cast<std::streamsize>(kChunk));
    text.resize(old + static_cast<std::size_t>(in.gcount()));
    if (text.size() > maxBytes) {
      throw ConfigError(path, "", "larger than " + sizeText(maxBytes) + ": not read");
    }
    if (in.eof()) break;
    if (!in) {
      const std::error_code ec(errno, std::generic_category());
      throw ConfigError(path, "", "cannot read: " + ec.message());
    }
  }
  if (in.bad()) throw ConfigError(path, "", "cannot read the file");
  return text;
}

LineReader::LineReader(std::istream& in, std::string file, std::size_t maxLineBytes)
    : in_(in), file_(std::move(file)), maxLineBytes_(maxLineBytes) {}

bool LineReader::next(std::string_view& line) {
  if (buffer_.size() != maxLineBytes_ + 2) buffer_.resize(maxLineBytes_ + 2);
  // istream::getline stores at most count - 1 characters and sets failbit when it stopped for
  // that reason; one character more than the limit tells a full line from a too long one.
  in_.getline(buffer_.data(), static_cast<std::streamsize>(maxLineBytes_ + 2));
  const auto extracted = static_cast<std::size_t>(in_.gcount());
  if (in_.bad()) {
    throw ConfigError(file_, "line " + std::to_string(lineNumber_ + 1), "cannot read the file");
  }
  if (extracted == 0 && in_.fail()) return false;  // end of the input
  ++lineNumber_;
  const bool delimiterRead = !in_.eof() && !in_.fail();
  std::size_t length = delimiterRead ? extracted - 1 : extracted;
  if (in_.fail() && !in_.eof()) {
    throw ConfigError(file_, "line " + std::to_string(lineNumber_),
                      "longer than " + sizeText(maxLineBytes_) + ": not a line of this format");
  }
  if (length > maxLineBytes_) {
    throw ConfigError(file_, "line " + std::to_string(lineNumber_),
                      "longer than " + sizeText(maxLineBytes_) + ": not a line of this format");
  }
  if (length > 0 && buffer_[length - 1] == '\r') --length;
  line = std::string_view(buffer_.data(), length);
  return true;
}

}  // namespace volcomp::config
