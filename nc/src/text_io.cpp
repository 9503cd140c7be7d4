#include "volcomp/nc/text_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "volcomp/nc/nc_error.hpp"

namespace volcomp::nc {
namespace {

[[noreturn]] void failErrno(const std::string& path, const char* what) {
  throw NcError(path, 0, 0, std::string(what) + ": " + std::strerror(errno));
}

}  // namespace

std::string_view StringSource::nextLines() {
  if (done_) return {};
  done_ = true;
  return text_;
}

FileSource::FileSource(const std::string& path, std::size_t blockBytes)
    : path_(path), buffer_(blockBytes) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) failErrno(path, "cannot open");
  struct stat st {};
  if (::fstat(fd_, &st) == 0 && S_ISREG(st.st_mode))
    total_ = static_cast<std::uint64_t>(st.st_size);
}

FileSource::~FileSource() {
  if (fd_ >= 0) ::close(fd_);
}

std::string_view FileSource::nextLines() {
  // Move the incomplete last line of the previous block to the front, then fill up.
  if (handedOut_ > 0) {
    std::memmove(buffer_.data(), buffer_.data() + handedOut_, carry_);
    handedOut_ = 0;
  }
  while (true) {
    if (eof_) {
      const std::size_t n = carry_;
      carry_ = 0;
      handedOut_ = n;
      return {buffer_.data(), n};
    }
    if (carry_ == buffer_.size()) buffer_.resize(buffer_.size() * 2);
    const ssize_t got = ::read(fd_, buffer_.data() + carry_, buffer_.size() - carry_);
    if (got < 0) {
      if (errno == EINTR) continue;
      failErrno(path_, "cannot read");
    }
    if (got == 0) {
      eof_ = true;
      continue;
    }
    read_ += static_cast<std::uint64_t>(got);
    const std::size_t filled = carry_ + static_cast<std::size_t>(got);
    const void* lastNewline = ::memrchr(buffer_.data(), '\n', filled);
    if (lastNewline == nullptr) {
      carry_ = filled;
      continue;
    }
    const auto complete =
        static_cast<std::size_t>(static_cast<const char*>(lastNewline) - buffer_.data()) + 1;
    carry_ = filled - complete;
    handedOut_ = complete;
    return {buffer_.data(), complete};
  }
}

FileSink::FileSink(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) failErrno(path, "cannot create");
  buffer_.reserve(1u << 20);
}

FileSink::~FileSink() {
  if (fd_ >= 0) ::close(fd_);
}

void FileSink::write(std::string_view text) {
  buffer_.append(text);
  if (buffer_.size() >= (1u << 20)) drain();
}

void FileSink::drain() {
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      failErrno(path_, "cannot write");
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
}

void FileSink::flush() {
  if (fd_ < 0) return;
  drain();
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) failErrno(path_, "cannot write");
}

}  // namespace volcomp::nc
