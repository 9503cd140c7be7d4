#pragma once
// The example machine calibrated the way a metrologist would do it, for the tests that need a
// model that differs from the truth as a real calibration does (the calibration end-to-end test,
// the VMC part of Dobariya, Patel and Jani with `volcomp nc`).
//
// volcomp-sim's TRUE machine (config/examples/vmc-xyfz-21-true.json) is "measured" over a grid in
// its travel with four tool offsets (a laser tracer's reflector on a cross-shaped holder), 0.5 um
// Gaussian noise per coordinate (seeded); `volcomp calibrate` identifies the 21 components with the
// example template (config/examples/vmc-xyfz-21-template.json).
//
// The true EXX is bidirectional (reversal ~4.5 um) and the calibration takes one curve per
// component, so the X reversal is measured like ISO 230-2 prescribes, in a second run with X
// approached from above: with every other component held at its stage-1 value, that run
// identifies EXX's negative-direction curve, which becomes the table's values_negative.
//
// The measurements come from `volcomp eval --points` on the true model with the direction of
// approach given (what the tracer sees at a point approached that way) plus the noise.
//
// Header only; the including test links nlohmann_json.

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "subprocess.hpp"

namespace volcomp::testutil {

/// Standard deviation of the simulated measurement per coordinate, mm.
inline constexpr double kMeasurementNoiseMm = 0.0005;

/// Seed of the simulated measurement's noise (one fixed draw, so the tests are repeatable).
inline constexpr unsigned kMeasurementSeed = 20261122;

/// Tool offsets of the measurement (mm): two lengths and two lateral offsets, so that the
/// angular errors of the tool-side Z carriage act through different arms.
inline const std::vector<std::array<double, 3>> kMeasurementTools{
    {0, 0, 120}, {0, 0, 220}, {100, 0, 120}, {0, 100, 120}};

/// Number of points of the measurement grid (writeMeasurementGrid).
inline constexpr std::size_t kMeasurementGridPoints = 21U * 11U * 9U;

/// Where the simulated calibration runs: the `volcomp` binary, the example configuration
/// directory and a working directory for its files.
struct CalibrationBench {
  std::string cli;
  std::string examplesDir;
  std::filesystem::path dir;

  std::string path(const std::string& name) const { return (dir / name).string(); }
  std::string example(const std::string& name) const { return examplesDir + "/" + name; }
  std::string trueModel() const { return example("vmc-xyfz-21-true.json"); }

  /// Runs `volcomp ARGS...` to its end, reading its stdout (so that a long summary cannot fill
  /// the pipe and block it); expects exit status 0. Returns the stdout text.
  std::string run(const std::vector<std::string>& args, const std::string& tag) const {
    using namespace std::chrono_literals;
    std::vector<std::string> argv{cli};
    argv.insert(argv.end(), args.begin(), args.end());
    Subprocess process(argv, path(tag + ".err"));
    std::string out;
    while (const auto line = process.readLine(60s)) out += *line + '\n';
    EXPECT_EQ(process.waitExit(10s), 0) << "volcomp " << tag << ": " << process.stderrText();
    return out;
  }

  nlohmann::json readJson(const std::string& file) const {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  }

  std::string writeJson(const std::string& name, const nlohmann::json& content) const {
    std::ofstream(dir / name) << content.dump(2);
    return path(name);
  }
};

/// The grid of the measurement: X every 42.5 mm (21), Y every 50 mm (11), Z every 62.5 mm (9)
/// over the whole travel, denser than the template's nodes so that the tables are determined
/// between them and the degree-6 straightness polynomials along Z by 9 levels.
inline std::string writeMeasurementGrid(const CalibrationBench& bench) {
  std::ofstream out(bench.dir / "grid.csv");
  out << "x,y,z\n";
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 10; ++j)
      for (int k = 0; k <= 8; ++k)
        out << 42.5 * i << ',' << 50 * j << ',' << -500 + 62.5 * k << '\n';
  return bench.path("grid.csv");
}

/// "Measures" the true model at the grid with each tool, approached in `direction` (e.g.
/// "+,+,+"), adding the noise; writes x,y,z,ex,ey,ez,tx,ty,tz (mm) to `name`.
inline std::string measureTrueMachine(const CalibrationBench& bench, const std::string& grid,
                                      const std::vector<std::array<double, 3>>& tools,
                                      const std::string& direction, std::mt19937& rng,
                                      const std::string& name) {
  std::normal_distribution<double> noise(0.0, kMeasurementNoiseMm);
  std::ofstream out(bench.dir / name);
  out.precision(9);
  out << "x,y,z,ex,ey,ez,tx,ty,tz\n";
  for (std::size_t t = 0; t < tools.size(); ++t) {
    const auto& tool = tools[t];
    std::ostringstream toolText;
    toolText << tool[0] << ',' << tool[1] << ',' << tool[2];
    const std::string exact = bench.path(name + "-exact" + std::to_string(t) + ".csv");
    bench.run({"eval", bench.trueModel(), "--points", grid, "--out", exact, "--tool",
               toolText.str(), "--direction", direction},
              name + "-eval" + std::to_string(t));
    std::ifstream in(exact);
    std::string line;
    std::getline(in, line);  // x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      std::vector<double> f;
      std::stringstream fields(line);
      for (std::string s; std::getline(fields, s, ',');) f.push_back(std::stod(s));
      if (f.size() != 12) continue;
      out << f[0] << ',' << f[1] << ',' << f[2];
      for (std::size_t k = 3; k < 6; ++k) out << ',' << f[k] + noise(rng);
      out << ',' << toolText.str() << '\n';
      ++rows;
    }
    EXPECT_EQ(rows, kMeasurementGridPoints) << exact;
  }
  return bench.path(name);
}

/// The files of a simulated calibration of the example machine.
struct CalibratedExample {
  std::string stage1;  ///< model of stage 1 (every axis approached in +)
  std::string report;  ///< calibration report of stage 1
  std::string stage2;  ///< model of stage 2 (X approached from above, EXX identified again)
  std::string model;   ///< the calibrated model: stage 1 with stage 2's EXX as values_negative
};

/// Measures the example TRUE machine and calibrates it in the two stages described above, with
/// the fixed seed; the calibrated model is written to `calibrated.json` in the bench's directory.
inline CalibratedExample calibrateExampleMachine(const CalibrationBench& bench) {
  std::mt19937 rng(kMeasurementSeed);
  const std::string grid = writeMeasurementGrid(bench);
  CalibratedExample files{bench.path("stage1.json"), bench.path("report.json"),
                          bench.path("stage2.json"), bench.path("calibrated.json")};

  // Stage 1: every axis approached in + (the tracer program's usual approach).
  const std::string forward =
      measureTrueMachine(bench, grid, kMeasurementTools, "+,+,+", rng, "forward.csv");
  bench.run({"calibrate", bench.example("vmc-xyfz-21-template.json"), forward, "--out",
             files.stage1, "--report", files.report},
            "calibrate1");
  const nlohmann::json stage1 = bench.readJson(files.stage1);

  // Stage 2: X approached from above, main tool only; the template is the stage-1 model with
  // EXX to identify again on the same nodes.
  const std::string reverse =
      measureTrueMachine(bench, grid, {kMeasurementTools[0]}, "-,+,+", rng, "reverse.csv");
  nlohmann::json reverseTemplate = stage1;
  reverseTemplate["components"]["EXX"] = {
      {"identify",
       {{"basis", "table"},
        {"positions", stage1["components"]["EXX"]["positions"]},
        {"interpolation", stage1["components"]["EXX"]["interpolation"]}}}};
  bench.run({"calibrate", bench.writeJson("reverse-template.json", reverseTemplate), reverse,
             "--out", files.stage2, "--report", bench.path("report2.json")},
            "calibrate2");
  nlohmann::json calibrated = stage1;
  calibrated["components"]["EXX"]["values_negative"] =
      bench.readJson(files.stage2)["components"]["EXX"]["values"];
  bench.writeJson("calibrated.json", calibrated);
  return files;
}

}  // namespace volcomp::testutil
