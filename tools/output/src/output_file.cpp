#include "volcomp/output/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <system_error>

#include "volcomp/config/printable.hpp"

namespace volcomp::output {
namespace {

namespace fs = std::filesystem;

std::string errnoText(int err) {
  return std::error_code(err, std::generic_category()).message();
}

/// Creates a new file beside `destination` that no one else has, with the permissions a file
/// created by open(2) gets (0666 minus the umask), and returns its path.
fs::path createTemporary(const fs::path& destination) {
  static std::atomic<unsigned> counter{0};
  const fs::path directory =
      destination.has_parent_path() ? destination.parent_path() : fs::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path candidate =
        directory / ("." + destination.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                     "-" + std::to_string(counter.fetch_add(1)));
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return candidate;
    }
    if (errno != EEXIST) {
      throw OutputError(destination, "cannot create a temporary file in " +
                                         config::printable(directory.string(), 512) + ": " +
                                         errnoText(errno));
    }
  }
  throw OutputError(destination, "cannot create a temporary file: every name is taken");
}

/// fsync(2) of a file by path: its data are on the disk before the rename makes it the target.
bool syncFile(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  ::close(fd);
  return ok;
}

}  // namespace

OutputError::OutputError(const fs::path& path, const std::string& problem)
    : std::runtime_error(config::printable(path.string(), 512) + ": " + problem), path_(path) {}

void refuseInputAsOutput(const fs::path& target, const std::vector<fs::path>& inputs) {
  for (const fs::path& input : inputs) {
    std::error_code ec;
    if (fs::equivalent(target, input, ec) && !ec) {
      throw OutputError(target, "is the input " + config::printable(input.string(), 512) +
                                    ": refusing to write over it (give another output path)");
    }
  }
}

OutputFile::OutputFile(fs::path target, const std::vector<fs::path>& inputs)
    : target_(std::move(target)), destination_(target_) {
  if (target_.empty()) throw OutputError(target_, "empty output path");
  refuseInputAsOutput(target_, inputs);
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(target_, ec);
  if (fs::is_symlink(link)) {
    destination_ = fs::canonical(target_, ec);
    if (ec) {
      throw OutputError(target_,
                        "is a symbolic link to a file that cannot be reached: " + ec.message());
    }
  }
  const fs::file_status status = fs::status(destination_, ec);
  if (fs::is_directory(status)) throw OutputError(target_, "is a directory, not a file");
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    // A device, a FIFO or a socket: written as it is, never replaced or removed.
    stream_.open(destination_, std::ios::binary);
    if (!stream_) throw OutputError(target_, "cannot open for writing: " + errnoText(errno));
    return;
  }
  // A file this user may not write stays as it is, as it would with a plain open(2).
  if (fs::exists(status) && ::access(destination_.c_str(), W_OK) != 0) {
    throw OutputError(target_, "cannot open for writing: " + errnoText(errno));
  }
  temporary_ = createTemporary(destination_);
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) {
    const int err = errno;
    fs::remove(temporary_, ec);
    temporary_.clear();
    throw OutputError(target_, "cannot open for writing: " + errnoText(err));
  }
  if (fs::exists(status)) {
    fs::permissions(temporary_, status.permissions(), fs::perm_options::replace, ec);
  }
}

OutputFile::~OutputFile() {
  if (committed_ || temporary_.empty()) return;
  stream_.close();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

void OutputFile::commit() {
  if (committed_) return;
  stream_.flush();
  const bool written = static_cast<bool>(stream_);
  const int writeErrno = errno;
  stream_.close();
  if (!written || !stream_) {
    throw OutputError(target_, "cannot write: " + errnoText(written ? errno : writeErrno));
  }
  if (temporary_.empty()) {
    committed_ = true;
    return;
  }
  if (!syncFile(temporary_)) throw OutputError(target_, "cannot write: " + errnoText(errno));
  std::error_code ec;
  fs::rename(temporary_, destination_, ec);
  if (ec) throw OutputError(target_, "cannot replace the file: " + ec.message());
  committed_ = true;
}

void writeOutputFile(const fs::path& target, std::string_view contents,
                     const std::vector<fs::path>& inputs) {
  OutputFile file(target, inputs);
  file.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  file.commit();
}

}  // namespace volcomp::output
