// The sample programs shipped with LinuxCNC (/usr/share/linuxcnc/ncfiles, package
// linuxcnc-uspace), each one either
//   - compensated as RS274/NGC (it is in the supported subset) and checked with LinuxCNC's
//     interpreter like the programs of rs274_test.cpp,
//   - or rejected with file:line:column, then flattened by rs274 -g and compensated through its
//     canonical form and checked,
//   - or rejected with a clear line as NGC and as canonical form (e.g. probing), or not runnable
//     by LinuxCNC's standalone interpreter at all (subroutine files, remapped codes...).
// One test per program; corpus_expected.txt says which of these each one of LinuxCNC 2.9's comes
// out as.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <variant>

#include "lcnc_path.hpp"
#include "lcnc_run.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::testing {
namespace {

constexpr const char* kCorpus = "/usr/share/linuxcnc/ncfiles";
constexpr double kToleranceMm = 0.001;
constexpr double kStepMm = 0.02;

// Errors of a real machine's size around the machine origin (the sample programs are drawn there):
// a kinked bidirectional positioning table, a bent axis, pitch, squareness and a grid.
const char* kCorpusModel = R"({
  "format": "volcomp-model/1", "name": "corpus machine", "topology": "XYFZ",
  "travel": {"X": [-1000, 1000], "Y": [-1000, 1000], "Z": [-1000, 1000]}, "tool": [0, 0, 100],
  "error_units": {"length": "um", "angle": "urad"},
  "components": {
    "EXX": {"positions": [-1000, -750, -500, -250, -100, 0, 100, 250, 500, 750, 1000],
            "values": [-14, -10, -8, -3, -1.5, 0, 1.2, 4, 7, 11, 15],
            "values_negative": [-10, -6, -4, 1, 2.5, 4, 5.2, 8, 11, 15, 19],
            "interpolation": "linear"},
    "EZX": {"polynomial": [0, 0.002, -0.00001]},
    "EYY": {"positions": [-1000, -500, 0, 500, 1000], "values": [-9, -2, 0, 5, 12],
            "interpolation": "cubic"},
    "EBX": {"polynomial": [2, 0.004]},
    "EAY": {"positions": [-1000, 0, 1000], "values": [-6, 0, 4], "interpolation": "quadratic"},
    "EC0Y": 25, "EB0Z": -15
  },
  "grids": [{"component": "EZ", "over": ["X", "Y"], "axes": {"X": [-1000, 0, 1000], "Y": [-1000, 1000]},
             "values": [[-5, 3], [-12, -4], [2, 6]]}]
})";

std::string toolTable() {
  std::string t;
  for (int i = 1; i <= 99; ++i)
    t += "T" + std::to_string(i) + " P" + std::to_string(i) + " Z0 D0.25\n";
  return t;
}

bool inches(const std::string& canonical) {
  return canonical.find("CANON_UNITS_INCHES") != std::string::npos;
}

struct Outcome {
  std::string category;
  std::string detail;
};

class Corpus : public ::testing::Test {
 protected:
  Corpus() {
    model_ = dir_.write("corpus-model.json", kCorpusModel);
    var_ = dir_.write("corpus.var", "5220 1\n");
    tbl_ = dir_.write("corpus.tbl", toolTable());
    const config::ModelDocument doc = config::loadModelFile(model_);
    machine_ = std::make_unique<model::MachineModel>(std::get<model::MachineModelSpec>(doc.spec));
  }

  // The compensated program checked against `originalCanonical` with LinuxCNC at full precision
  // when the Python binding runs it, else with rs274 (then within its 4 printed decimals).
  void check(const std::string& name, const std::string& originalCanonical,
             const std::string& compensated, bool originalExact) {
    SCOPED_TRACE(name);
    const Command full = linuxCncFullPrecision(dir_, compensated, var_);
    std::string canonical = full.out;
    double slack = 1e-5;
    if (full.status != 0) {
      const Command coarse = rs274(dir_, compensated, var_, tbl_);
      ASSERT_EQ(coarse.status, 0) << coarse.err;
      canonical = coarse.out;
      slack = 0.5e-4 * (inches(canonical) ? 25.4 : 1.0) * std::sqrt(3.0) + 1e-5;
      ++coarseChecks_;
    }
    if (!originalExact) slack += 0.5e-4 * (inches(originalCanonical) ? 25.4 : 1.0) * std::sqrt(3.0);
    const auto o = parseCanonical(originalCanonical, Vec3::Zero());
    const auto c = parseCanonical(canonical, Vec3::Zero());
    const PathCheck result = checkCompensation(*machine_, o, c, kStepMm);
    EXPECT_LE(result.worst(), kToleranceMm + slack)
        << result.worstAt << " (tip->original " << result.tipToOriginalMm << ", original->tip "
        << result.originalToTipMm << ", rapid ends " << result.rapidEndsMm << ")";
    samples_ += result.tipSamples + result.originalSamples;
  }

  Outcome process(const std::filesystem::path& file) {
    const std::string name = std::filesystem::relative(file, kCorpus).string();
    const std::string out = (dir_.path() / "comp.ngc").string();
    const std::string common = " --work-offsets " + volcomp::testing::quoted(var_) +
                               " --tool-table " + volcomp::testing::quoted(tbl_) +
                               " --machine-units inch --start 0,0,0 --quiet";
    const CliRun ngc = runCli(dir_, "nc " + volcomp::testing::quoted(model_) + " " +
                                        volcomp::testing::quoted(file.string()) + " --out " +
                                        volcomp::testing::quoted(out) + common);
    if (ngc.status == 0) {
      const Command full = linuxCncFullPrecision(dir_, file.string(), var_);
      if (full.status == 0) {
        check(name, full.out, out, true);
        return {"compensated as RS274/NGC", ""};
      }
      const Command original = rs274(dir_, file.string(), var_, tbl_);
      if (original.status != 0) return {"compensated, not runnable by rs274", original.err};
      check(name, original.out, out, false);
      return {"compensated as RS274/NGC", ""};
    }
    EXPECT_EQ(ngc.status, 2) << name << ": " << ngc.err;
    static const std::regex located(R"(^volcomp: [^:]+:\d+(:\d+)?: .+\n$)");
    EXPECT_TRUE(std::regex_match(ngc.err, located)) << name << ": " << ngc.err;
    const Command canon = rs274(dir_, file.string(), var_, tbl_);
    const std::string firstError = ngc.err.substr(0, ngc.err.size() - 1);
    if (canon.status != 0) {
      return {"rejected; rs274 cannot run it standalone either",
              firstError + " | rs274: " + canon.err.substr(0, canon.err.find('\n', 10))};
    }
    const std::string canonFile = dir_.write("program.canon", canon.out);
    const CliRun flat = runCli(dir_, "nc " + volcomp::testing::quoted(model_) + " " +
                                         volcomp::testing::quoted(canonFile) + " --out " +
                                         volcomp::testing::quoted(out) + " --start 0,0,0 --quiet");
    if (flat.status != 0) {
      EXPECT_EQ(flat.status, 2) << name << ": " << flat.err;
      EXPECT_TRUE(std::regex_match(flat.err, located)) << name << ": " << flat.err;
      return {"rejected as RS274/NGC and as canonical form",
              flat.err.substr(0, flat.err.size() - 1)};
    }
    // The canonical form is the input here: the flat program must follow it.
    check(name, canon.out, out, true);
    return {"compensated through the rs274 canonical form", firstError};
  }

  TempDir dir_;
  std::string model_, var_, tbl_;
  std::unique_ptr<model::MachineModel> machine_;
  long samples_ = 0;
  long coarseChecks_ = 0;
};

// Every .ngc file of the corpus, relative to it, sorted: one test each, so that they run side by
// side.
std::vector<std::string> corpusPrograms() {
  std::vector<std::string> names;
  if (!std::filesystem::is_directory(kCorpus)) return names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kCorpus)) {
    if (entry.is_regular_file() && entry.path().extension() == ".ngc")
      names.push_back(std::filesystem::relative(entry.path(), kCorpus).string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

// What each program of LinuxCNC 2.9's corpus comes out as (corpus_expected.txt: the category, a
// tab, the program). A program the list does not name (another LinuxCNC) may come out as any.
std::map<std::string, std::string> expectedOutcomes() {
  std::map<std::string, std::string> expected;
  std::ifstream in(VOLCOMP_CORPUS_EXPECTED);
  std::string line;
  while (std::getline(in, line)) {
    const auto tab = line.find('\t');
    if (line.empty() || line[0] == '#' || tab == std::string::npos) continue;
    expected[line.substr(tab + 1)] = line.substr(0, tab);
  }
  return expected;
}

class CorpusProgram : public Corpus, public ::testing::WithParamInterface<std::string> {};

TEST_P(CorpusProgram, CompensatedAndCheckedOrRejectedAtALine) {
  const Outcome o = process(std::filesystem::path(kCorpus) / GetParam());
  std::cout << GetParam() << ": " << o.category << (o.detail.empty() ? "" : "  [" + o.detail + "]")
            << "\n";
  if (samples_ > 0) {
    std::cout << "  checked with " << samples_ << " samples"
              << (coarseChecks_ > 0 ? " at rs274's 4 decimals (tool changes)"
                                    : " at full precision")
              << "\n";
  }
  const auto expected = expectedOutcomes();
  const auto it = expected.find(GetParam());
  if (it != expected.end()) {
    EXPECT_EQ(o.category, it->second);
  }
}

std::string testName(const ::testing::TestParamInfo<std::string>& info) {
  std::string name;
  for (const char c : info.param) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(LinuxCncSamples, CorpusProgram, ::testing::ValuesIn(corpusPrograms()),
                         testName);

// The list the programs are held to: LinuxCNC's corpus is there, and the list still describes
// it (more than 100 programs, the two ways of compensating well represented, no program the
// corpus lost).
TEST(CorpusExpectations, DescribeTheInstalledCorpus) {
  const std::vector<std::string> programs = corpusPrograms();
  ASSERT_GT(programs.size(), 100u) << "LinuxCNC's sample programs (linuxcnc-uspace) not found";
  std::map<std::string, int> counts;
  for (const auto& [program, category] : expectedOutcomes()) {
    ++counts[category];
    EXPECT_TRUE(std::binary_search(programs.begin(), programs.end(), program)) << program;
  }
  EXPECT_GT(counts["compensated as RS274/NGC"], 5);
  EXPECT_GT(counts["compensated through the rs274 canonical form"], 20);
}

}  // namespace
}  // namespace volcomp::testing
