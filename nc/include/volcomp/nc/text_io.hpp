#pragma once
/// Streams of program text for the compensation: a source hands out pieces made of whole lines,
/// a sink takes text. Files are read and written in blocks of about 1 MiB, so memory does not
/// grow with the program. I/O failures throw NcError naming the file.

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace volcomp::nc {

class TextSource {
 public:
  virtual ~TextSource() = default;
  /// The next piece of text made of whole lines (only the very last line may lack its newline);
  /// empty at the end. The view stays valid until the next call.
  virtual std::string_view nextLines() = 0;
  /// Bytes handed out so far and the total (0 when unknown), for progress.
  virtual std::uint64_t bytesRead() const noexcept = 0;
  virtual std::uint64_t totalBytes() const noexcept = 0;
};

class TextSink {
 public:
  virtual ~TextSink() = default;
  virtual void write(std::string_view text) = 0;
  virtual void flush() {}
};

/// All of a string at once.
class StringSource final : public TextSource {
 public:
  explicit StringSource(std::string text) : text_(std::move(text)) {}
  std::string_view nextLines() override;
  std::uint64_t bytesRead() const noexcept override { return done_ ? text_.size() : 0; }
  std::uint64_t totalBytes() const noexcept override { return text_.size(); }

 private:
  std::string text_;
  bool done_ = false;
};

class StringSink final : public TextSink {
 public:
  void write(std::string_view text) override { text_.append(text); }
  const std::string& text() const noexcept { return text_; }

 private:
  std::string text_;
};

/// A file read in blocks of `blockBytes` (lines longer than a block make the block grow).
class FileSource final : public TextSource {
 public:
  explicit FileSource(const std::string& path, std::size_t blockBytes = 1u << 20);
  ~FileSource() override;
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;
  std::string_view nextLines() override;
  std::uint64_t bytesRead() const noexcept override { return read_; }
  std::uint64_t totalBytes() const noexcept override { return total_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::vector<char> buffer_;
  std::size_t carry_ = 0;  // bytes of an incomplete line kept at the front of buffer_
  std::size_t handedOut_ = 0;
  bool eof_ = false;
  std::uint64_t read_ = 0;
  std::uint64_t total_ = 0;
};

/// A file written through a buffer of about 1 MiB; the file is created (truncated).
class FileSink final : public TextSink {
 public:
  explicit FileSink(const std::string& path);
  ~FileSink() override;
  FileSink(const FileSink&) = delete;
  FileSink& operator=(const FileSink&) = delete;
  void write(std::string_view text) override;
  /// Writes what is buffered and closes the file; throws NcError when that fails.
  void flush() override;

 private:
  void drain();
  std::string path_;
  int fd_ = -1;
  std::string buffer_;
};

}  // namespace volcomp::nc
