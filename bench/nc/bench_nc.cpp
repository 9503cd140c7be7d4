// volcomp-bench-nc: the speed of `volcomp nc` on a large program (the benchmark).
//
//   volcomp-bench-nc MODEL.json [--lines N] [--repeat R] [--dir DIR] [--keep]
//
// Writes a program of N lines (default 1,000,000) of G1 moves over the whole travel of the model
// (a 3-D surface finishing raster: rows along X, 0.85 mm steps on the VMC-850, Z following a
// surface, modal G1 with X Y Z on every line as CAM posts write them), then compensates it R
// times (default 5) with the library exactly as the CLI does (file in, file out, streamed in
// chunks), and prints the median time, lines/s, the time of each stage (read + interpret, offset
// solves, planning + splitting + checking, formatting + writing) and the peak RSS of the process
// (VmHWM), with the wall time and the thread's CPU time. Pin it: taskset -c 1 volcomp-bench-nc ...
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "volcomp/config/model_file.hpp"
#include "volcomp/nc/compensator.hpp"
#include "volcomp/nc/ngc_reader.hpp"
#include "volcomp/nc/text_io.hpp"

namespace {

using namespace volcomp;

long peakRssKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  }
  return -1;
}

double threadCpuS() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// A finishing raster over the travel [lo, hi] of X and Y, Z on a wavy surface in the upper half of
// the Z travel; lines of "X.. Y.. Z.." after a G1 on the first move.
void writeProgram(const std::string& path, long lines, const std::array<double, 3>& lo,
                  const std::array<double, 3>& hi) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) throw std::runtime_error("cannot write " + path);
  const long perRow = 1000;
  const long rows = std::max(1L, (lines - 4) / (perRow + 1));
  const double dx = (hi[0] - lo[0]) / static_cast<double>(perRow);
  const double dy = (hi[1] - lo[1]) / static_cast<double>(rows);
  const double zMid = lo[2] + 0.75 * (hi[2] - lo[2]);
  const double zAmp = 0.1 * (hi[2] - lo[2]);
  std::fprintf(f, "(volcomp-bench-nc: %ld-line finishing raster)\nG21 G90 G17 G94\n", lines);
  std::fprintf(f, "G0 X%.3f Y%.3f Z%.3f\n", lo[0], lo[1], hi[2]);
  long written = 3;
  bool first = true;
  for (long r = 0; r <= rows && written < lines; ++r) {
    const double y = lo[1] + dy * static_cast<double>(r);
    for (long i = 0; i <= perRow && written < lines; ++i) {
      const long k = (r % 2 == 0) ? i : perRow - i;
      const double x = lo[0] + dx * static_cast<double>(k);
      const double z = zMid + zAmp * std::sin(x / 53.0) * std::cos(y / 41.0);
      std::fprintf(f, first ? "G1 X%.3f Y%.3f Z%.3f F3000\n" : "X%.3f Y%.3f Z%.3f\n", x, y, z);
      first = false;
      ++written;
    }
  }
  std::fprintf(f, "M2\n");
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr
        << "usage: volcomp-bench-nc MODEL.json [--lines N] [--repeat R] [--dir DIR] [--keep]\n";
    return 2;
  }
  const std::string modelPath = argv[1];
  long lines = 1000000;
  int repeat = 5;
  std::string dir = std::filesystem::temp_directory_path().string();
  bool keep = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--lines" && i + 1 < argc)
      lines = std::stol(argv[++i]);
    else if (a == "--repeat" && i + 1 < argc)
      repeat = std::stoi(argv[++i]);
    else if (a == "--dir" && i + 1 < argc)
      dir = argv[++i];
    else if (a == "--keep")
      keep = true;
    else {
      std::cerr << "volcomp-bench-nc: unknown argument " << a << "\n";
      return 2;
    }
  }
  try {
    const config::ModelDocument doc = config::loadModelFile(modelPath);
    const auto& spec = std::get<model::MachineModelSpec>(doc.spec);
    std::array<double, 3> lo{}, hi{};
    for (int k = 0; k < 3; ++k) {
      const auto& t = spec.travelMm[static_cast<std::size_t>(k)];
      lo[static_cast<std::size_t>(k)] = t ? (*t)[0] : 0.0;
      hi[static_cast<std::size_t>(k)] = t ? (*t)[1] : 500.0;
    }
    const std::string in = dir + "/volcomp-bench-nc-in.ngc";
    const std::string out = dir + "/volcomp-bench-nc-out.ngc";
    writeProgram(in, lines, lo, hi);
    auto model = std::make_shared<const model::MachineModel>(spec);
    std::vector<double> times, cpuTimes;
    nc::NcReport last;
    for (int r = 0; r < repeat; ++r) {
      nc::OffsetField field(model, model::EvalMode::Exact);
      nc::CompensateOptions options;
      nc::NgcReader reader(in, {}, {}, std::nullopt, nc::decimalsForTolerance(options.toleranceMm));
      nc::Compensator compensator(field, options, std::nullopt);
      nc::FileSource source(in);
      nc::FileSink sink(out);
      const double c0 = threadCpuS();
      const auto t0 = std::chrono::steady_clock::now();
      last = compensator.run(reader, source, sink);
      times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      cpuTimes.push_back(threadCpuS() - c0);
    }
    std::sort(times.begin(), times.end());
    std::sort(cpuTimes.begin(), cpuTimes.end());
    const double median = times[times.size() / 2];
    const double cpuMedian = cpuTimes[cpuTimes.size() / 2];
    const auto size = std::filesystem::file_size(in);
    std::printf(
        "program: %ld lines, %.1f MB, %ld feed moves; output %ld lines (%ld pieces added)\n",
        last.linesIn, static_cast<double>(size) / 1e6, last.feedMoves, last.linesOut,
        last.piecesAdded);
    std::printf("time: median %.3f s of %d (min %.3f, max %.3f): %.0f lines/s, %.0f ns/line\n",
                median, repeat, times.front(), times.back(),
                static_cast<double>(last.linesIn) / median,
                1e9 * median / static_cast<double>(last.linesIn));
    // On a loaded machine the wall time includes waiting for the core; the thread's CPU time
    // is the work done (the file I/O is in the page cache).
    std::printf("cpu time (this thread): median %.3f s (min %.3f, max %.3f): %.0f lines/s\n",
                cpuMedian, cpuTimes.front(), cpuTimes.back(),
                static_cast<double>(last.linesIn) / cpuMedian);
    const double n = static_cast<double>(last.linesIn) / 1e9;
    std::printf(
        "stages (last run, ns/line): read+interpret %.0f, offsets %.0f (%ld solves: %.0f "
        "ns each), plan+split+check %.0f, format+write %.0f\n",
        last.readS / n, last.offsetsS / n, last.offsetSolves,
        1e9 * last.offsetsS / static_cast<double>(last.offsetSolves), last.splitS / n,
        last.writeS / n);
    const double staged = last.readS + last.offsetsS + last.splitS + last.writeS;
    std::printf(
        "stages (share): read+interpret %.0f %%, offsets %.0f %%, plan+split+check %.0f %%, "
        "format+write %.0f %%\n",
        100 * last.readS / staged, 100 * last.offsetsS / staged, 100 * last.splitS / staged,
        100 * last.writeS / staged);
    std::printf("deviation: max %.3f um checked, %.3f um with the allowance; peak RSS %ld kB\n",
                last.maxDeviationMm * 1e3, last.maxBoundMm * 1e3, peakRssKb());
    if (!keep) {
      std::filesystem::remove(in);
      std::filesystem::remove(out);
    }
  } catch (const std::exception& e) {
    std::cerr << "volcomp-bench-nc: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
