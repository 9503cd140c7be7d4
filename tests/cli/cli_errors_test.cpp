// Exit status 2 with exactly one line on stderr for bad arguments and bad files; --help and
// --version.

#include <gtest/gtest.h>

#include "run_cli.hpp"

namespace volcomp::testing {
namespace {

const char* kModel =
    R"({"format": "volcomp-model/1", "topology": "FXYZ", "components": {"EXX": 1}})";

void expectUsageError(const CliRun& run, const std::string& fragment) {
  EXPECT_EQ(run.status, 2) << run.out << run.err;
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.errLines(), 1) << run.err;
  EXPECT_EQ(run.err.rfind("volcomp: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(fragment), std::string::npos) << run.err << "lacks: " << fragment;
}

TEST(CliErrors, BadArguments) {
  TempDir dir;
  const std::string model = quoted(dir.write("m.json", kModel));
  expectUsageError(runCli(dir, ""), "subcommand is required");
  expectUsageError(runCli(dir, "frobnicate"), "volcomp");
  expectUsageError(runCli(dir, "eval"), "model is required");
  expectUsageError(runCli(dir, "eval " + model), "give --at X,Y,Z or --points");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2"),
                   "--at X,Y,Z (mm): expected 3 comma-separated numbers, got \"1,2\"");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,x,3"), "\"x\" is not a finite number");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2,3 --tool 0,0"), "--tool");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2,3 --direction +,+"),
                   "--direction: expected three of +, - or 0");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2,3 --bogus"), "--bogus");
  expectUsageError(runCli(dir, "eval " + model + " --points in.csv"), "--out");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2,3 --points in.csv --out o.csv"),
                   "excludes");
  expectUsageError(runCli(dir, "eval " + model + " --at 1,2,3 --mode fast"), "--mode");
}

TEST(CliErrors, BadFiles) {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.json").string();
  expectUsageError(runCli(dir, "eval " + quoted(missing) + " --at 1,2,3"),
                   missing + ": cannot open file");
  const std::string broken = dir.write("broken.json", "{\n  \"format\": \"volcomp-model/1\",\n}");
  expectUsageError(runCli(dir, "eval " + quoted(broken) + " --at 1,2,3"),
                   broken + ": invalid JSON: parse error at line 3, column 1");
  const std::string badComponent =
      dir.write("bad.json", R"({"format": "volcomp-model/1", "topology": "FXYZ", "components": {
        "EXX": {"positions": [0, 10, 5], "values": [0, 1, 2]}}})");
  expectUsageError(runCli(dir, "check " + quoted(badComponent)),
                   badComponent + ": components.EXX.positions[2]: expected a position greater");
  expectUsageError(runCli(dir, "eval " + quoted(badComponent) + " --at 1,2,3"),
                   "components.EXX.positions[2]");
}

// Bad files whose refusal could run long (a long token in invalid JSON, an implausible value
// with its hints) are still one line naming the file, under 300 characters.
TEST(CliErrors, LongRefusalsAreOneShortLineNamingTheFile) {
  TempDir dir;
  const std::string longToken =
      dir.write("long.json", "{\"format\": \"volcomp-model/1\", \"name\": \"" +
                                 std::string(4000, 'n') + "\x01\"}");
  expectUsageError(runCli(dir, "eval " + quoted(longToken) + " --at 1,2,3"),
                   longToken + ": invalid JSON: parse error at line 1, column ");
  const std::string typedAsMm =
      dir.write("mm.json", R"({"format": "volcomp-model/1", "topology": "XYFZ",
        "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]},
        "error_units": {"length": "mm", "angle": "mrad"},
        "components": {"EXX": {"positions": [0, 850], "values": [0, 15.6]}}})");
  expectUsageError(runCli(dir, "check " + quoted(typedAsMm)), typedAsMm + ": components.EXX");
  for (const std::string& file : {longToken, typedAsMm}) {
    const CliRun run = runCli(dir, "check " + quoted(file));
    EXPECT_LE(run.err.size(), 300u) << run.err;
  }
}

TEST(CliErrors, HelpAndVersion) {
  TempDir dir;
  const CliRun help = runCli(dir, "--help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("eval"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("check"), std::string::npos) << help.out;
  const CliRun evalHelp = runCli(dir, "eval --help");
  EXPECT_EQ(evalHelp.status, 0);
  for (const char* option : {"--at", "--points", "--out", "--tool", "--direction", "--json"}) {
    EXPECT_NE(evalHelp.out.find(option), std::string::npos) << option;
  }
  const CliRun checkHelp = runCli(dir, "check --help");
  EXPECT_EQ(checkHelp.status, 0);
  EXPECT_NE(checkHelp.out.find("Validate a model file"), std::string::npos) << checkHelp.out;
  const CliRun version = runCli(dir, "--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_EQ(version.out.rfind("volcomp ", 0), 0u) << version.out;
}

}  // namespace
}  // namespace volcomp::testing
