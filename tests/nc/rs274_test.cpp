// `volcomp nc` checked by LinuxCNC's own interpreter: rs274 (and, for full precision, the same
// interpreter through its Python binding) reads the original and the compensated program; the
// machine described by the model, moving along the compensated canonical motions, must put the
// tool tip on the original path within the tolerance + 0.1 um (rs274 prints 4 decimals: 0.05 um
// per axis in mm), both ways, sampled every 0.01 mm; rapids at their end points.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <variant>

#include <nlohmann/json.hpp>

#include "lcnc_path.hpp"
#include "lcnc_run.hpp"
#include "volcomp/config/model_file.hpp"

namespace volcomp::testing {
namespace {

constexpr double kStepMm = 0.01;
constexpr double kRs274SlackMm = 1e-4;  // rs274's 4 decimals in mm
constexpr double kFullSlackMm = 1e-5;   // full precision: what is left is our own rounding

std::string examples(const std::string& name) {
  return std::string(VOLCOMP_EXAMPLES) + "/" + name;
}

// Values in inches (rs274's machine units) with every digit, so that both interpreters read the
// same doubles.
std::string inch(double mm) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", mm / 25.4);
  return buffer;
}

// G54 (300, 200, -300) mm, G55 (100, 100, -250) mm; tools 1 (Z 50 mm) and 2 (Z 80.5 mm).
std::string varFile() {
  return "5220 1\n5221 " + inch(300) + "\n5222 " + inch(200) + "\n5223 " + inch(-300) + "\n5241 " +
         inch(100) + "\n5242 " + inch(100) + "\n5243 " + inch(-250) + "\n";
}

std::string toolTable() {
  return "T1 P1 Z" + inch(50) + " D6 ;6 mm end mill\nT2 P2 Z" + inch(80.5) + " D10 ;10 mm\n";
}

model::MachineModel loadModel(const std::string& file) {
  const config::ModelDocument doc = config::loadModelFile(file);
  return model::MachineModel(std::get<model::MachineModelSpec>(doc.spec));
}

// A machine with errors far beyond a real one's, so that moves must be split a lot: a bent X axis,
// a kinked positioning error (linear table every 25 mm), a wavy Y axis, a bidirectional Y table,
// squareness, and a sagging bridge as a grid.
const char* kStrongModel = R"({
  "format": "volcomp-model/1", "name": "strong errors for tests", "topology": "XYFZ",
  "travel": {"X": [0, 850], "Y": [0, 500], "Z": [-500, 0]}, "tool": [0, 0, 120],
  "error_units": {"length": "um", "angle": "urad"},
  "components": {
    "EZX": {"polynomial": [0, 0.9, -0.0011]},
    "EXX": {"positions": [0, 25, 50, 75, 100, 125, 150, 175, 200, 225, 250, 275, 300, 325, 350,
                          375, 400, 425, 450, 475, 500, 525, 550, 575, 600, 625, 650, 675, 700,
                          725, 750, 775, 800, 825, 850],
            "values": [0, 3, 1, 6, 4, 9, 5, 12, 8, 14, 9, 16, 13, 18, 15, 22, 17, 25, 19, 27, 24,
                       30, 26, 33, 29, 36, 32, 40, 35, 43, 38, 46, 42, 49, 45],
            "interpolation": "linear"},
    "EYY": {"positions": [0, 100, 200, 300, 400, 500], "values": [0, 8, 3, 12, 6, 15],
            "values_negative": [6, 14, 9, 18, 12, 21], "interpolation": "cubic"},
    "EBX": {"polynomial": [0, 0.5, -0.0004]},
    "EAY": {"positions": [0, 250, 500], "values": [0, 40, 10], "interpolation": "quadratic"},
    "EC0Y": 60, "EB0Z": -40
  },
  "grids": [{"component": "EZ", "over": ["X", "Y"],
             "axes": {"X": [0, 212.5, 425, 637.5, 850], "Y": [0, 250, 500]},
             "values": [[0, -20, 0], [-10, -45, -10], [-15, -60, -15], [-10, -45, -10], [0, -20, 0]]}]
})";

struct Scenario {
  Scenario(std::string n, std::string p, std::string m = examples("vmc-xyfz-21.json"))
      : name(std::move(n)), program(std::move(p)), model(std::move(m)) {}
  std::string name;
  std::string program;
  std::string model;
  std::string extraArgs;
  bool fullPrecision = true;  // also check with lcnc_canon.py (not with tool changes)
  double toleranceMm = 0.001;
  double minUncompensatedMm = 0.005;  // the original program is at least this far off
};

// Numbers every line that is not a comment (N10, N20 ...): rs274 prints the N word with every
// canonical command, which ties the pieces of a compensated move to their programmed move.
std::string numbered(const std::string& program) {
  std::istringstream in(program);
  std::string line, out;
  int n = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '(' && line[0] != '%')
      line = "N" + std::to_string(n += 10) + " " + line;
    out += line + "\n";
  }
  return out;
}

class LinuxCncCheck : public ::testing::Test {
 protected:
  void run(const Scenario& s) {
    SCOPED_TRACE(s.name);
    const std::string program = dir_.write("part.ngc", numbered(s.program));
    const std::string var = dir_.write("part.var", varFile());
    const std::string tbl = dir_.write("part.tbl", toolTable());
    const std::string out = (dir_.path() / "part-comp.ngc").string();
    const std::string report = (dir_.path() / "report.json").string();
    char tolerance[32];
    std::snprintf(tolerance, sizeof tolerance, "%.9g", s.toleranceMm);
    const CliRun cli =
        runCli(dir_, "nc " + quoted(s.model) + " " + quoted(program) + " --out " + quoted(out) +
                         " --report " + quoted(report) + " --work-offsets " + quoted(var) +
                         " --tool-table " + quoted(tbl) + " --machine-units inch --start 0,0,0" +
                         " --tolerance " + tolerance + " " + s.extraArgs);
    ASSERT_EQ(cli.status, 0) << cli.err;
    const nlohmann::json r = nlohmann::json::parse(readFile(report));
    EXPECT_LE(r["deviation_mm"]["max_bound"].get<double>(), s.toleranceMm);
    EXPECT_EQ(r["deviation_mm"]["unresolved_pieces"].get<long>(), 0);
    EXPECT_EQ(r["not_converged"]["points"].get<long>(), 0);
    const model::MachineModel model = loadModel(s.model);

    // rs274 on both programs, from machine zero as rs274 assumes.
    const Command original = rs274(dir_, program, var, tbl);
    ASSERT_EQ(original.status, 0) << original.err;
    const Command compensated = rs274(dir_, out, var, tbl);
    ASSERT_EQ(compensated.status, 0) << compensated.err << "\n" << readFile(out);
    const auto o = parseCanonical(original.out, Vec3::Zero());
    const auto c = parseCanonical(compensated.out, Vec3::Zero());
    ASSERT_FALSE(o.empty());
    const PathCheck check = checkCompensation(model, o, c, kStepMm);
    // In an inch program rs274 prints 0.0001 in: up to 2.2 um off on each of the two paths.
    const bool inch = original.out.find("CANON_UNITS_INCHES") != std::string::npos;
    const double slack = inch ? 2 * 0.5e-4 * 25.4 * std::sqrt(3.0) : kRs274SlackMm;
    EXPECT_LE(check.worst(), s.toleranceMm + slack)
        << check.worstAt << "\ntip->original " << check.tipToOriginalMm << " original->tip "
        << check.originalToTipMm << " rapid ends " << check.rapidEndsMm;
    EXPECT_GT(check.tipSamples, 100);
    EXPECT_GT(check.originalSamples, 100);
    // The check has teeth: the original program on this machine misses its own path.
    const PathCheck uncompensated = checkCompensation(model, o, o, 0.5);
    EXPECT_GT(uncompensated.worst(), s.minUncompensatedMm);
    last_ = check;

    if (!s.fullPrecision) return;
    const Command fullOriginal = linuxCncFullPrecision(dir_, program, var);
    ASSERT_EQ(fullOriginal.status, 0) << fullOriginal.err;
    const Command fullCompensated = linuxCncFullPrecision(dir_, out, var);
    ASSERT_EQ(fullCompensated.status, 0) << fullCompensated.err;
    // This binding starts at the program origin; every scenario's first move sets all axes.
    const auto fo = parseCanonical(fullOriginal.out, Vec3::Zero());
    const auto fc = parseCanonical(fullCompensated.out, Vec3::Zero());
    const PathCheck full = checkCompensation(model, fo, fc, kStepMm);
    EXPECT_LE(full.worst(), s.toleranceMm + kFullSlackMm)
        << full.worstAt << "\ntip->original " << full.tipToOriginalMm << " original->tip "
        << full.originalToTipMm << " rapid ends " << full.rapidEndsMm;
  }

  TempDir dir_;
  PathCheck last_;
};

TEST_F(LinuxCncCheck, LongLinesAcrossTheTravel) {
  run(Scenario(
      "lines",
      "(long lines through the whole travel)\nG21 G90 G17 G54\nG0 X-250 Y-150 Z0\n"
      "G1 X500 Y250 Z-150 F2000\nG1 X-250 Y280 Z-50\nG1 X540 Y-190 Z100\nG1 X-250 Y-150 Z0\n"
      "G0 Z50\nM2\n"));
}

TEST_F(LinuxCncCheck, ArcsInEveryPlaneHelicesAndFullCircles) {
  run(Scenario("arcs",
               "G21 G90 G54 G0 X0 Y0 Z0\nG17 G2 X100 Y0 I50 J0 F1000\nG3 X150 Y50 R50\n"
               "G2 X50 Y50 R-50\nG3 I-50 J0 Z-20 P2\nG17 G2 X50 Y-50 I0 J-50 Z-30\n"
               "G18 G2 X100 Z-30 I25 K0\nG3 X50 Z-80 R50\nG18 G2 X50 Z-80 I40 K0 Y-60 P3\n"
               "G19 G3 Y0 Z-80 J30 K0\nG19 G2 Y-40 Z-40 R40\nG2 Y-40 Z-40 J0 K-30 X10\n"
               "G17 G1 X0 Y0 Z0\nM2\n"));
}

TEST_F(LinuxCncCheck, AbsoluteArcCentres) {
  run(Scenario("g90.1",
               "G21 G90 G54 G0 X0 Y0 Z0\nG90.1 G2 X200 Y0 I100 J0 F1000\nG3 X250 Y50 I200 J50\n"
               "G91.1 G2 X300 Y0 I50 J0\nG90.1 G18 G3 X200 Z0 I250 K0\nG17 G1 X0 Y0 Z0\nM2\n"));
}

TEST_F(LinuxCncCheck, IncrementalProgram) {
  std::string p = "G21 G90 G54 G0 X-200 Y-100 Z0\nG91 F1500\n";
  for (int i = 0; i < 12; ++i) {
    p += "G1 X" + std::to_string(37.5 + i) + " Y" + std::to_string(i % 2 == 0 ? 20 : -7) + " Z-3\n";
  }
  p += "G2 X40 Y0 I20 J0\nG3 X0 Y40 I0 J20 Z5\nG1 X-300 Y-60 Z0\nG90 G0 Z50\nM2\n";
  run(Scenario("g91", p));
}

TEST_F(LinuxCncCheck, InchProgram) {
  Scenario s{"g20",
             "G20 G90 G54 G0 X-9 Y-5 Z0\nG1 X12 Y6 Z-4 F40\nG2 X14 Y6 I1 J0\n"
             "G3 X12 Y8 R2\nG18 G2 X10 Z-4 I-1 K0\nG91 G17 G1 X-5 Y-3 Z2\nG90 G0 Z1\nM2\n"};
  run(s);
}

TEST_F(LinuxCncCheck, WorkOffsetsFromParametersAndJson) {
  const std::string program =
      "G21 G90 G55 G0 X0 Y0 Z0\nG1 X500 Y300 Z-100 F1000\nG54 G1 X0 Y0 Z0\n"
      "G59 G1 X10 Y10 Z-10\nM2\n";
  run(Scenario("var", program));
  // The same offsets given as JSON for volcomp (rs274 keeps reading the .var file).
  const std::string json =
      dir_.write("offsets.json",
                 R"({"format": "volcomp-work-offsets/1", "units": "mm", "active": "G54",
          "coordinate_systems": {"G54": [300, 200, -300], "G55": [100, 100, -250]}})");
  Scenario s{"json", program};
  s.extraArgs = "--work-offsets " + quoted(json);
  run(s);
}

TEST_F(LinuxCncCheck, ToolLengthOffsets) {
  Scenario s{"g43",
             "G21 G90 G54\nT1 M6\nG43 H1\nG0 X0 Y0 Z50\nG1 Z0 F500\nG1 X400 Y200 Z-80\n"
             "G0 Z60\nT2 M6\nG43 H2 G0 X400 Y0 Z40\nG1 Z-20\nG2 X300 Y0 R50\nG43 H1 G1 X0 Y0\n"
             "G49 G0 Z100\nM2\n"};
  s.fullPrecision = false;  // the Python binding cannot change tools outside LinuxCNC
  run(s);
}

TEST_F(LinuxCncCheck, BidirectionalTablesAndReversals) {
  // A raster along X: every line reverses X, whose positioning table is bidirectional.
  std::string p = "G21 G90 G54 G0 X-280 Y-180 Z0\nF3000\n";
  for (int i = 0; i < 8; ++i) {
    p += std::string("G1 X") + (i % 2 == 0 ? "520" : "-280") + "\nG1 Y" +
         std::to_string(-180 + 40 * (i + 1)) + "\n";
  }
  p += "G0 Z50\nM2\n";
  run(Scenario("raster", p));
  const nlohmann::json r = nlohmann::json::parse(readFile(dir_.path() / "report.json"));
  EXPECT_GE(r["reversal_moves"].get<long>(), 7);
  EXPECT_GE(last_.markedMoves, 7);
}

TEST_F(LinuxCncCheck, StrongErrorsManyPieces) {
  const std::string model = dir_.write("strong.json", kStrongModel);
  Scenario s{"strong",
             "G21 G90 G54 G0 X-290 Y-190 Z0\nG1 X530 Y270 Z-150 F2000\nG2 X430 Y170 R100\n"
             "G18 G2 X230 Z-150 I-100 K0\nG1 X-290 Y-190 Z0\nG19 G2 Y200 Z0 J195 K0\nM2\n",
             model};
  s.minUncompensatedMm = 0.05;
  run(s);
  const nlohmann::json r = nlohmann::json::parse(readFile(dir_.path() / "report.json"));
  EXPECT_GT(r["pieces_added"].get<long>(), 100);
}

TEST_F(LinuxCncCheck, GantryWithGridAndCoarseTolerance) {
  Scenario s{"gantry",
             "G21 G90 G54 G0 X-290 Y-190 Z0\nG1 X1650 Y1250 Z150 F2000\nG1 X-290 Y1250\n"
             "G2 X-290 Y-190 R720\nM2\n",
             examples("gantry-fxyz-grid.json")};
  s.toleranceMm = 0.004;
  run(s);
}

TEST_F(LinuxCncCheck, CanonicalFormOfAProgramOutsideTheSubset) {
  // Parameters, a loop and a canned cycle: rejected as NGC, compensated through rs274 -g.
  const std::string program = dir_.write(
      "loops.ngc",
      "G21 G90 G54 G0 X0 Y0 Z10\n#1 = 0\no100 while [#1 LT 5]\n  G1 X[#1 * 80] Y[#1 * 30] Z-5 "
      "F800\n  G2 X[#1 * 80 + 40] Y[#1 * 30] R20\n  #1 = [#1 + 1]\no100 endwhile\n"
      "G98 G81 X100 Y100 Z-20 R2\nX200\nG80 G0 Z50\nM2\n");
  const std::string var = dir_.write("part.var", varFile());
  const std::string model = examples("vmc-xyfz-21.json");
  const CliRun rejected = runCli(dir_, "nc " + quoted(model) + " " + quoted(program) + " --out " +
                                           quoted((dir_.path() / "x.ngc").string()));
  EXPECT_EQ(rejected.status, 2);
  EXPECT_NE(rejected.err.find("loops.ngc:2:1: parameters"), std::string::npos) << rejected.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "x.ngc"));

  const Command canon = rs274(dir_, program, var, "");
  ASSERT_EQ(canon.status, 0) << canon.err;
  const std::string canonFile = dir_.write("loops.canon", canon.out);
  const std::string out = (dir_.path() / "flat.ngc").string();
  const CliRun cli = runCli(dir_, "nc " + quoted(model) + " " + quoted(canonFile) + " --out " +
                                      quoted(out) + " --start 0,0,0");
  ASSERT_EQ(cli.status, 0) << cli.err;
  EXPECT_NE(cli.err.find("(canon,"), std::string::npos) << cli.err;
  const Command flat = rs274(dir_, out, var, "");
  ASSERT_EQ(flat.status, 0) << flat.err << readFile(out);
  const auto o = parseCanonical(canon.out, Vec3::Zero());
  const auto c = parseCanonical(flat.out, Vec3::Zero());
  const PathCheck check = checkCompensation(loadModel(model), o, c, kStepMm);
  EXPECT_LE(check.worst(), 0.001 + kRs274SlackMm) << check.worstAt;
  EXPECT_GT(check.tipSamples, 100);
}

}  // namespace
}  // namespace volcomp::testing
