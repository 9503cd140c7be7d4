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

TEST(CliPoints, BadRowNamesFileLineAndColumnAndLeavesNoOutput) {
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string out = (dir.path() / "out.csv").string();
  // Each bad row with what the one line on stderr must say after "IN: line 3".
  const std::pair<const char*, const char*> cases[] = {
      {"1,2", ": expected 3 fields (x,y,z), got 2"},
      {"1,2,3,4", ": expected 3 fields (x,y,z), got 4"},
      {"1,two,3", ", column y: expected a finite number, got \"two\""},
      {"1,2,nan", ", column z: expected a finite number, got \"nan\""},
      {"1,,3", ", column y: expected a finite number, got \"\""}};
  for (const auto& [bad, message] : cases) {
    SCOPED_TRACE(bad);
    const std::string in = dir.write("in.csv", std::string("x,y,z\n1,2,3\n") + bad + "\n4,5,6\n");
    const CliRun run =
        runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
    EXPECT_EQ(run.status, 2);
    EXPECT_EQ(run.errLines(), 1) << run.err;
    EXPECT_NE(run.err.find(in + ": line 3" + message), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

// A bad row used to truncate an existing output first and remove it afterwards. The
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
  // The shared CSV reader names the column and shows the field that is not a number.
  EXPECT_NE(run.err.find("line 2, column x: expected a finite number, got "
                         "\"\\x1b[2J\\x1b]0;owned\\x07\""),
            std::string::npos)
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
  EXPECT_NE(run.err.find(in + ": line 1: unknown column \"a\" (expected x,y,z and optionally "
                              "tx,ty,tz,direction"),
            std::string::npos)
      << run.err;
}

TEST(CliPoints, ColumnsInAnyOrderWithToolDirectionCommentsAndUnits) {
  // The same points as --tool/--direction on the command line give, row by row, the same
  // numbers bit for bit when they come per point from the file, in any column order, with
  // comments, unit suffixes and columns of a measurement file that eval does not read.
  TempDir dir;
  const std::string model = dir.write("m.json", kModel);
  const std::string in = dir.write("in.csv",
                                   "# tracer points, two tools, X approached from both sides\n"
                                   "tz,direction,x_um,y,z,tx,ty,ex\n"
                                   "200,-++,412500,250.25,-123.456,10,0,0.001\n"
                                   "# comment\n"
                                   "120,+++,100000,3,-4,0,0,0.002\n");
  const std::string out = (dir.path() / "out.csv").string();
  const CliRun run =
      runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " + quoted(out));
  ASSERT_EQ(run.status, 0) << run.err;
  const std::vector<std::string> rows = lines(readFile(out));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz,tx,ty,tz,direction");
  EXPECT_TRUE(rows[1].ends_with(",10,0,200,-++")) << rows[1];
  EXPECT_TRUE(rows[2].ends_with(",0,0,120,+++")) << rows[2];
  const char* single[] = {"--at 412.5,250.25,-123.456 --tool 10,0,200 --direction -,+,+",
                          "--at 100,3,-4 --tool 0,0,120 --direction +,+,+"};
  for (std::size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE(single[i]);
    const CliRun one = runCli(dir, "eval " + quoted(model) + " " + single[i] + " --json");
    ASSERT_EQ(one.status, 0) << one.err;
    const nlohmann::json j = nlohmann::json::parse(one.out);
    const std::string row = rows[i + 1];
    const std::vector<double> values = numbersOf(row.substr(0, row.rfind(',')));
    const char* keys[] = {"position", "error", "angular_error", "offset"};
    for (std::size_t k = 0; k < 4; ++k) {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(values[k * 3 + axis], j[keys[k]][axis].get<double>()) << keys[k] << " " << axis;
      }
    }
  }
}

TEST(CliPoints, AToolFarFromTheCalibratedToolsIsWarnedAbout) {
  TempDir dir;
  nlohmann::json calibrated = nlohmann::json::parse(kModel);
  calibrated["calibration"] = {{"tools_mm", {{0, 0, 120}, {0, 0, 220}}}};
  const std::string model = dir.write("m.json", calibrated.dump());
  // Between the two calibrated lengths: no warning.
  CliRun run = runCli(dir, "eval " + quoted(model) + " --at 1,2,-3 --tool 0,0,170");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.err, "");
  // 80 mm beyond the longer one: one warning line saying how far and which tools.
  run = runCli(dir, "eval " + quoted(model) + " --at 1,2,-3 --tool 0,0,300");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("warning: tool (0, 0, 300) mm is 80 mm outside the tools the model was "
                         "calibrated with, (0, 0, 120); (0, 0, 220) mm"),
            std::string::npos)
      << run.err;
  // Per-point tools: each far tool once, with its first line.
  const std::string in = dir.write("in.csv",
                                   "x,y,z,tx,ty,tz\n1,2,-3,0,0,150\n1,2,-3,50,0,120\n"
                                   "4,5,-6,50,0,120\n");
  run = runCli(dir, "eval " + quoted(model) + " --points " + quoted(in) + " --out " +
                        quoted((dir.path() / "o.csv").string()));
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_NE(run.err.find("tool (50, 0, 120) mm (first at " + in + " line 3) is 50 mm outside"),
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
