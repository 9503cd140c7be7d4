// readTextFile, openTextFile and LineReader: what a file itself can be (missing, a directory, too
// large, lines too long) is reported as such, with the file and line, without reading unbounded
// amounts into memory.

#include <gtest/gtest.h>

#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "temp_files.hpp"
#include "volcomp/config/config_error.hpp"
#include "volcomp/config/text_input.hpp"

namespace volcomp::config {
namespace {

using volcomp::testing::TempDir;

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<std::string> linesOf(const std::string& text, std::size_t max = kMaxLineBytes) {
  std::istringstream in(text);
  LineReader reader(in, "t.csv", max);
  std::vector<std::string> out;
  std::string_view line;
  while (reader.next(line)) {
    out.emplace_back(line);
    EXPECT_EQ(reader.lineNumber(), out.size());
  }
  return out;
}

TEST(TextInput, ReadsAFile) {
  TempDir dir;
  const std::string path = dir.write("a.json", "{\"a\": 1}\n");
  EXPECT_EQ(readTextFile(path), "{\"a\": 1}\n");
}

TEST(TextInput, ADirectoryIsNamedAsSuch) {
  TempDir dir;
  const std::string path = dir.path().string();
  EXPECT_EQ(errorOf([&] { readTextFile(path); }), path + ": is a directory, not a file");
  EXPECT_EQ(errorOf([&] { openTextFile(path); }), path + ": is a directory, not a file");
}

TEST(TextInput, AMissingFileSaysWhy) {
  TempDir dir;
  const std::string path = (dir.path() / "absent.json").string();
  EXPECT_EQ(errorOf([&] { readTextFile(path); }),
            path + ": cannot open file: No such file or directory");
}

TEST(TextInput, AFileLargerThanTheLimitIsRefused) {
  TempDir dir;
  const std::string path = dir.write("big.json", std::string(3000, ' '));
  EXPECT_EQ(errorOf([&] { readTextFile(path, 2048); }), path + ": larger than 2 KiB: not read");
  EXPECT_EQ(readTextFile(path, 3000).size(), 3000u);
}

TEST(LineReaderTest, SplitsLinesDroppingCarriageReturns) {
  EXPECT_EQ(linesOf("a,b\r\n\nc\n"), (std::vector<std::string>{"a,b", "", "c"}));
  EXPECT_EQ(linesOf("last line without newline"),
            (std::vector<std::string>{"last line without newline"}));
  EXPECT_EQ(linesOf(""), std::vector<std::string>{});
  EXPECT_EQ(linesOf(std::string("nul\0byte\n", 9)),
            (std::vector<std::string>{std::string("nul\0byte", 8)}));
}

TEST(LineReaderTest, TakesLinesUpToTheLimitExactly) {
  const std::string full(16, 'x');
  EXPECT_EQ(linesOf(full + "\n" + full, 16), (std::vector<std::string>{full, full}));
  EXPECT_EQ(linesOf(full + "\r\n", 17), (std::vector<std::string>{full}));
}

TEST(LineReaderTest, ALongerLineIsAnErrorNamingIt) {
  const std::string full(16, 'x');
  for (const std::string& text :
       {"ok\n" + full + "y\nnext\n", "ok\n" + full + "yyyyyyyyyyyyyyyyyyyy", "ok\n" + full + "y"}) {
    SCOPED_TRACE(text);
    EXPECT_EQ(errorOf([&] { linesOf(text, 16); }),
              "t.csv: line 2: longer than 16 bytes: not a line of this format");
  }
}

// A CSV line of a million columns: refused with a clear error, not split into a million fields.
TEST(LineReaderTest, AMillionColumnLineIsRefused) {
  std::string text = "x,y,z\n";
  for (int i = 0; i < 1000000; ++i) text += "1,";
  text += "1\n";
  EXPECT_EQ(errorOf([&] { linesOf(text); }),
            "t.csv: line 2: longer than 1 MiB: not a line of this format");
}

}  // namespace
}  // namespace volcomp::config
