// `volcomp eval MODEL --points IN.csv --out OUT.csv`: header, one row per input row, full
// precision (each row equals the single-point JSON evaluation bit for bit), bad rows.

#include <gtest/gtest.h>

#include <charconv>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

const char* kModel = R"({"format": "volcomp-model/1", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "um", "angle": "urad"},
  "components": {
    "EXX": {"positions": [0, 400, 850], "values": [0, 6.2, 15.6], "values_negative": [4, 10, 19],
            "interpolation": "cubic"},
    "EBX": {"polynomial": [0, 0.02, -1e-5]}, "ECZ": 3.3, "EC0Y": 18.5, "EZY": -2},
  "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [0, 850], "Y": [0, 500]},
             "values": [[0, 3], [5, 11]]}]})";

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    out.push_back(text.substr(start, end - start));
    start = end == std::string::npos ? text.size() : end + 1;
  }
  return out;
}

std::vector<double> numbersOf(const std::string& row) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= row.size()) {
    const std::size_t comma = std::min(row.find(',', start), row.size());
    double v = 0;
    const auto result = std::from_chars(row.data() + start, row.data() + comma, v);
    EXPECT_EQ(result.ec, std::errc()) << row;
    EXPECT_EQ(result.ptr, row.data() + comma) << row;
    out.push_back(v);
    start = comma + 1;
  }
  return out;
}

TEST(CliPoints, BatchMatchesSinglePointsExactly) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  // Spaces, CRLF line ends, a blank line and upper-case header names are tolerated.
  const std::string in = dir.write(
      "in.csv", " X , y ,Z\r\n0,0,0\r\n412.5, 250.25 ,-123.456\r\n\r\n850,500,-500\r\n1e2,3,-4\n");
  const std::string out = (dir.path() / "out.csv").string();
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const std::vector<std::string> rows = lines(readFile(out));
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0], "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz");
  const char* points[] = {"0,0,0", "412.5,250.25,-123.456", "850,500,-500", "100,3,-4"};
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(points[i]);
    const std::vector<double> row = numbersOf(rows[i + 1]);
    ASSERT_EQ(row.size(), 12u);
    const CliRun single = runCli(dir, "eval " + quoted(model) + " --at " + points[i] + " --json");
    ASSERT_EQ(single.status, 0) << single.err;
    const nlohmann::json j = nlohmann::json::parse(single.out);
    const char* keys[] = {"position", "error", "angular_error", "offset"};
    for (std::size_t k = 0; k < 4; ++k) {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        // Both outputs are shortest round-trip texts of the same doubles: equal bit for bit.
        EXPECT_EQ(row[k * 3 + axis], j[keys[k]][axis].get<double>()) << keys[k] << " " << axis;
      }
    }
  }
}

TEST(CliPoints, OutsideTheTravelIsCountedOnStderr) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.write("in.csv", "x,y,z\n1,1,-1\n900,1,-1\n-5,1,-1\n");
  const std::string out = (dir.path() / "out.csv").string();
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("2 of 3 points outside the travel (first at " + in + " line 3)"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(lines(readFile(out)).size(), 4u);
}

TEST(CliPoints, BadRowNamesFileAndLineAndLeavesNoOutput) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string out = (dir.path() / "out.csv").string();
  for (const char* bad : {"1,2", "1,2,3,4", "1,two,3", "1,2,nan", "1,,3"}) {
    SCOPED_TRACE(bad);
    const std::string in = dir.write("in.csv", std::string("x,y,z\n1,2,3\n") + bad + "\n4,5,6\n");
    const CliRun run =
        runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.errLines(), 1) << run.err;
    EXPECT_NE(run.err.find(in + ": line 3: expected three finite numbers x,y,z"), std::string::npos)
        << run.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

// Issue 13: a bad row used to truncate an existing output first and remove it afterwards. The
// output is now written beside it and renamed only when every row was good.
TEST(CliPoints, BadRowLeavesAnExistingOutputAsItWas) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string out = dir.write("out.csv", "precious results\n");
  const std::string in = dir.write("in.csv", "x,y,z\n1,2,3\n1,2\n");
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_EQ(readFile(out), "precious results\n");
  // Nothing else is left in the directory (no temporary file).
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    files += entry.path().filename().string().rfind(".out.csv", 0) == 0 ? 100 : 1;
  }
  EXPECT_EQ(files, 5u);  // m.json, out.csv, in.csv, stdout.txt, stderr.txt
}

TEST(CliPoints, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string points = "x,y,z\n1,2,3\n";
  const std::string in = dir.write("in.csv", points);
  for (const std::string& out : {in, (dir.path() / "." / "in.csv").string(), model}) {
    SCOPED_TRACE(out);
    const CliRun run =
        runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.errLines(), 1) << run.err;
    EXPECT_NE(run.err.find(": refusing to write over it"), std::string::npos) << run.err;
    EXPECT_EQ(readFile(in), points);
    EXPECT_EQ(readFile(model), kModel);
  }
}

TEST(CliPoints, ADeviceAsOutputIsWrittenNotReplaced) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.write("in.csv", "x,y,z\n1,2,3\n");
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out /dev/null");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
}

TEST(CliPoints, ADirectoryAsInputIsNamedAsSuch) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.path().string();
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " +
                                     quoted((dir.path() / "o.csv").string()));
  EXPECT_EQ(run.status, 2);
  EXPECT_NE(run.err.find(in + ": is a directory, not a file"), std::string::npos) << run.err;
}

// Whatever a bad row holds, the message shows it escaped and shortened: no terminal escape
// reaches the terminal, no invalid UTF-8, no 100 kB line.
TEST(CliPoints, ABadRowIsShownEscapedAndShortened) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.write(
      "in.csv", "x,y,z\n\x1b[2J\x1b]0;owned\x07,\xff\xfe," + std::string(100000, '9') + "x\n");
  const std::string out = (dir.path() / "out.csv").string();
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_EQ(run.err.find('\x1b'), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find('\xff'), std::string::npos) << run.err;
  EXPECT_LT(run.err.size(), 400u);
  EXPECT_NE(run.err.find("got \"\\x1b[2J\\x1b]0;owned\\x07,\\xff\\xfe,999"), std::string::npos)
      << run.err;
}

TEST(CliPoints, BadHeader) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.write("in.csv", "a,b,c\n1,2,3\n");
  const std::string out = (dir.path() / "out.csv").string();
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find(in + ": line 1: expected the header x,y,z, got \"a,b,c\""),
            std::string::npos)
      << run.err;
}

TEST(CliPoints, MissingInputFile) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = (dir.path() / "absent.csv").string();
  const CliRun run = runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " +
                                     quoted((dir.path() / "o.csv").string()));
  EXPECT_EQ(run.status, 2);
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find(in + ": cannot open file"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace volcomp::testing
