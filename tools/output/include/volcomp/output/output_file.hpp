#pragma once
/// Writing the files a program produces without ever destroying one: the one way every verb of
/// `volcomp`, `volcomp-sim` and the libraries behind them write an output file (models, reports,
/// CSV results, controller tables, records). A new verb that writes a file uses OutputFile or
/// writeOutputFile and nothing else.
///
/// The rules:
/// - The content goes to a new temporary file beside the target (".NAME.tmp-PID-N" in the same
///   directory, created exclusively by this program), never into the target itself.
/// - commit() flushes it, syncs it to disk and renames it over the target in one step: whoever
///   reads the target sees the old file or the whole new one, never a part, even after a crash.
/// - Without commit() (a bad input row, an exception, any error) the temporary file is removed
///   and the target, if it existed, is left exactly as it was. Nothing the program did not create
///   is ever removed.
/// - A target that is one of the program's inputs (the same file, however spelt: a relative path,
///   a symbolic or a hard link) is refused before anything is written.
/// - A target that exists and is not a regular file, such as /dev/stdout, /dev/null or a FIFO, is
///   written in place: it is never replaced, renamed over or removed. A directory is refused.
/// - A symbolic link as the target: the file it points to is replaced and the link kept.
/// - An existing target keeps its permission bits; a new one gets 0666 minus the umask, as with
///   any other way of creating a file. (The owner is the writer's; the directory must be writable.)
/// Errors are OutputError exceptions: "PATH: what went wrong" (the path passed through
/// volcomp::config::printable), caught where the program reports errors.

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace volcomp::output {

/// An output file that could not be written (or was refused); what() names the path.
class OutputError : public std::runtime_error {
 public:
  OutputError(const std::filesystem::path& path, const std::string& problem);
  const std::filesystem::path& path() const noexcept { return path_; }

 private:
  std::filesystem::path path_;
};

/// One output file being written (see the rules above).
class OutputFile {
 public:
  /// Prepares `target`: refuses a directory and a target that is the same file as one of
  /// `inputs`, then creates the temporary file (or opens a non-regular target in place).
  explicit OutputFile(std::filesystem::path target,
                      const std::vector<std::filesystem::path>& inputs = {});
  /// Removes the temporary file unless commit() succeeded.
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Where the content goes.
  std::ostream& stream() noexcept { return stream_; }
  /// Flushes, syncs and renames the temporary file over the target. Throws OutputError when a
  /// write failed (a full disk) or the rename is refused; the target is then untouched.
  void commit();
  /// The path as given.
  const std::filesystem::path& target() const noexcept { return target_; }

 private:
  std::filesystem::path target_;
  std::filesystem::path destination_;  // target_, or the file a symbolic link points to
  std::filesystem::path temporary_;    // empty when written in place
  std::ofstream stream_;
  bool committed_ = false;
};

/// Writes `contents` to `target` by the rules above, in one call.
void writeOutputFile(const std::filesystem::path& target, std::string_view contents,
                     const std::vector<std::filesystem::path>& inputs = {});

/// Throws OutputError when `target` is the same existing file as one of `inputs` (device and
/// inode compared, so any spelling, symbolic or hard link of the input is caught).
void refuseInputAsOutput(const std::filesystem::path& target,
                         const std::vector<std::filesystem::path>& inputs);

}  // namespace volcomp::output
