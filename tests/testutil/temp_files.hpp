#pragma once
// A temporary directory for one test (the one TempDir of the test suites), removed with
// everything in it at the end of the test, or kept for inspection (its path on stderr) when the
// test failed.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

namespace volcomp::testing {

class TempDir {
 public:
  TempDir() {
    // A short name: a unix socket's path inside it must fit in sockaddr_un (108 bytes).
    std::string pattern = (std::filesystem::temp_directory_path() / "volcomp-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed";
    path_ = pattern;
  }
  ~TempDir() {
    if (::testing::Test::HasFailure()) {
      std::cerr << "kept " << path_.string() << " for inspection\n";
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Writes `text` to a file of that name in the directory; returns its full path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = path_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace volcomp::testing
