// volcomp::output: output files are written whole or not at all, beside the target and renamed,
// never over an input, never removing what the program did not create.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_files.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::output {
namespace {

namespace fs = std::filesystem;
using volcomp::testing::TempDir;

std::string contentOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Every entry of the directory (temporary files included), sorted.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "(no error)";
}

mode_t modeOf(const fs::path& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0);
  return st.st_mode & 07777;
}

TEST(OutputFileTest, WritesANewFileWithTheUsualPermissions) {
  TempDir dir;
  const fs::path target = dir.path() / "out.csv";
  const mode_t mask = ::umask(022);
  writeOutputFile(target, "x,y,z\n");
  ::umask(mask);
  EXPECT_EQ(contentOf(target), "x,y,z\n");
  EXPECT_EQ(modeOf(target), 0644u);
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"out.csv"});
}

TEST(OutputFileTest, ReplacesAnExistingFileKeepingItsPermissions) {
  TempDir dir;
  const fs::path target = dir.write("out.csv", "old");
  fs::permissions(target, fs::perms(0640), fs::perm_options::replace);
  writeOutputFile(target, "new");
  EXPECT_EQ(contentOf(target), "new");
  EXPECT_EQ(modeOf(target), 0640u);
}

TEST(OutputFileTest, WithoutCommitTheTargetIsUntouchedAndNothingIsLeft) {
  TempDir dir;
  const fs::path target = dir.write("out.csv", "precious");
  {
    OutputFile file(target);
    file.stream() << "half a result";
    // The target is not written while the file is being written.
    EXPECT_EQ(contentOf(target), "precious");
    EXPECT_EQ(entries(dir.path()).size(), 2u);  // the target and the temporary file beside it
  }
  EXPECT_EQ(contentOf(target), "precious");
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"out.csv"});
  // Nor is a target that did not exist created.
  { OutputFile file(dir.path() / "fresh.csv"); }
  EXPECT_EQ(entries(dir.path()), std::vector<std::string>{"out.csv"});
}

TEST(OutputFileTest, AnInputIsNeverAnOutputHoweverItIsNamed) {
  TempDir dir;
  const fs::path input = dir.write("in.csv", "x,y,z\n1,2,3\n");
  fs::create_symlink(input, dir.path() / "link.csv");
  fs::create_hard_link(input, dir.path() / "hard.csv");
  fs::create_directory(dir.path() / "sub");
  for (const fs::path& target : {input, dir.path() / "sub" / ".." / "in.csv",
                                 dir.path() / "link.csv", dir.path() / "hard.csv"}) {
    SCOPED_TRACE(target.string());
    const std::string error = errorOf([&] { writeOutputFile(target, "oops", {input}); });
    EXPECT_NE(error.find("is the input " + input.string() + ": refusing to write over it"),
              std::string::npos)
        << error;
    EXPECT_EQ(contentOf(input), "x,y,z\n1,2,3\n");
  }
}

TEST(OutputFileTest, ADeviceIsWrittenInPlaceAndNeverReplaced) {
  writeOutputFile("/dev/null", "discarded\n");
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  // Without commit nothing is removed either.
  { OutputFile file("/dev/null"); }
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST(OutputFileTest, ADirectoryIsRefused) {
  TempDir dir;
  EXPECT_EQ(errorOf([&] { writeOutputFile(dir.path(), "x"); }),
            dir.path().string() + ": is a directory, not a file");
}

TEST(OutputFileTest, ASymbolicLinkKeepsPointingAtTheNewContent) {
  TempDir dir;
  const fs::path real = dir.write("real.csv", "old");
  const fs::path link = dir.path() / "link.csv";
  fs::create_symlink(real, link);
  writeOutputFile(link, "new");
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(contentOf(real), "new");
}

TEST(OutputFileTest, AMissingDirectoryIsReportedWithThePath) {
  TempDir dir;
  const fs::path target = dir.path() / "no-such-dir" / "out.csv";
  const std::string error = errorOf([&] { writeOutputFile(target, "x"); });
  EXPECT_EQ(error.rfind(target.string() + ": cannot create a temporary file in ", 0), 0u) << error;
  EXPECT_NE(error.find("No such file or directory"), std::string::npos) << error;
}

}  // namespace
}  // namespace volcomp::output
