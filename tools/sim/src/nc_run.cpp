#include "volcomp/sim/nc_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <unordered_map>

#include <CLI/CLI.hpp>

#include "volcomp/config/config_error.hpp"
#include "volcomp/config/printable.hpp"
#include "volcomp/nc/nc_error.hpp"
#include "volcomp/sim/sim_config.hpp"

namespace volcomp::sim {
namespace {

using V3 = nc::Vec3;

struct Piece {
  V3 a, b;
  MotionDirections dirs{};
};

// Reference path as short straight pieces (arcs within 1e-5 mm), with the direction in which each
// axis last moved there.
std::vector<Piece> referencePieces(const std::vector<NcProgramMove>& moves,
                                   const std::string& file) {
  std::vector<Piece> pieces;
  MotionDirections dirs{};
  for (const NcProgramMove& m : moves) {
    const int n = arcChords(m, 1e-5, file);
    V3 a = m.move.startMm;
    for (int i = 1; i <= n; ++i) {
      const V3 b = m.move.at(static_cast<double>(i) / n);
      for (int k = 0; k < 3; ++k) {
        if (b[k] != a[k]) dirs[static_cast<std::size_t>(k)] = b[k] > a[k] ? 1 : -1;
      }
      if (m.move.kind != nc::MoveKind::Rapid) pieces.push_back(Piece{a, b, dirs});
      a = b;
    }
  }
  return pieces;
}

V3 closestOn(const Piece& p, const V3& x) {
  const V3 ab = p.b - p.a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((x - p.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return p.a + t * ab;
}

// The nearest reference piece to a point, exactly: pieces are filed in a hash grid of cubic cells
// (a long piece in every cell along it), and the search grows ring by ring of cells around the
// point until no unvisited cell can hold anything nearer. A heuristic "look near the last match"
// picks the wrong pass where the path runs over itself (a helix under a full circle) and then
// reports the distance to that pass.
class PathIndex {
 public:
  explicit PathIndex(const std::vector<Piece>& pieces) : pieces_(pieces) {
    for (std::size_t i = 0; i < pieces_.size(); ++i) {
      const Piece& p = pieces_[i];
      const int n = std::max(1, static_cast<int>(std::ceil((p.b - p.a).norm() / kCellMm)));
      for (int j = 0; j < n; ++j) {
        const V3 a = p.a + (p.b - p.a) * (static_cast<double>(j) / n);
        const V3 b = p.a + (p.b - p.a) * (static_cast<double>(j + 1) / n);
        const Cell lo = cellOf(a.cwiseMin(b)), hi = cellOf(a.cwiseMax(b));
        for (long x = lo[0]; x <= hi[0]; ++x)
          for (long y = lo[1]; y <= hi[1]; ++y)
            for (long z = lo[2]; z <= hi[2]; ++z) {
              std::vector<std::uint32_t>& bucket = cells_[key({x, y, z})];
              if (bucket.empty() || bucket.back() != i) {
                bucket.push_back(static_cast<std::uint32_t>(i));
              }
            }
      }
    }
  }

  std::size_t nearest(const V3& x) const {
    std::size_t best = pieces_.size();
    double bestD = std::numeric_limits<double>::infinity();
    const auto consider = [&](std::size_t i) {
      const double d = (closestOn(pieces_[i], x) - x).norm();
      if (d < bestD) {
        bestD = d;
        best = i;
      }
    };
    const Cell c = cellOf(x);
    for (long r = 0; r <= kMaxRings; ++r) {
      for (long dx = -r; dx <= r; ++dx)
        for (long dy = -r; dy <= r; ++dy)
          for (long dz = -r; dz <= r; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
            const auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
            if (it == cells_.end()) continue;
            for (const std::uint32_t i : it->second) consider(i);
          }
      // Every cell not yet visited is at least r whole cells away from the point.
      if (bestD <= static_cast<double>(r) * kCellMm) return best;
    }
    for (std::size_t i = 0; i < pieces_.size(); ++i) consider(i);
    return best;
  }

 private:
  using Cell = std::array<long, 3>;
  static constexpr double kCellMm = 0.5;
  static constexpr long kMaxRings = 8;

  static Cell cellOf(const V3& x) {
    return {static_cast<long>(std::floor(x[0] / kCellMm)),
            static_cast<long>(std::floor(x[1] / kCellMm)),
            static_cast<long>(std::floor(x[2] / kCellMm))};
  }
  static std::uint64_t key(const Cell& c) {
    const auto part = [](long v) { return static_cast<std::uint64_t>(v) & 0x1fffffu; };
    return part(c[0]) | part(c[1]) << 21 | part(c[2]) << 42;
  }

  const std::vector<Piece>& pieces_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace

nlohmann::json NcRunReport::toJson() const {
  return nlohmann::json{{"samples", samples},       {"path_mm", pathMm},
                        {"rms_um", rmsUm},          {"max_um", maxUm},
                        {"max_at_mm", maxAtMm},     {"rms_axis_um", rmsAxisUm},
                        {"max_axis_um", maxAxisUm}, {"marked_moves", markedMoves}};
}

namespace {

// The contour error of tool-tip positions against the reference path, accumulated sample by
// sample: the part of nc-run that a program run and a recorded run share.
class ContourMeter {
 public:
  ContourMeter(const NcProgramSpec& reference, const std::string& trueModel)
      : pieces_(referencePieces(readNcProgram(reference), reference.file)),
        index_(pieces_),
        trueError_(loadTrueError(trueModel)) {
    if (pieces_.empty()) {
      throw config::ConfigError(reference.file, "", "the reference program has no feed moves");
    }
  }

  /// Directions of travel on the reference path nearest to `q`.
  MotionDirections directionsNear(const V3& q) const { return pieces_[index_.nearest(q)].dirs; }

  /// One sample: the axes stand at `q`, moving in `dirs`.
  void add(const V3& q, const MotionDirections& dirs) {
    const Vec3 err = trueError_({q[0], q[1], q[2]}, dirs);
    const V3 tip = q + V3(err[0], err[1], err[2]);
    const V3 error = tip - closestOn(pieces_[index_.nearest(tip)], tip);
    const double norm = error.norm() * 1000.0;
    sumSq_ += norm * norm;
    if (norm > r_.maxUm || r_.samples == 0) {
      r_.maxUm = norm;
      r_.maxAtMm = {q[0], q[1], q[2]};
    }
    for (std::size_t k = 0; k < 3; ++k) {
      const double c = error[static_cast<int>(k)] * 1000.0;
      sumSqAxis_[k] += c * c;
      r_.maxAxisUm[k] = std::max(r_.maxAxisUm[k], std::abs(c));
    }
    ++r_.samples;
  }

  NcRunReport& report() {
    if (r_.samples > 0) {
      r_.rmsUm = std::sqrt(sumSq_ / static_cast<double>(r_.samples));
      for (std::size_t k = 0; k < 3; ++k) {
        r_.rmsAxisUm[k] = std::sqrt(sumSqAxis_[k] / static_cast<double>(r_.samples));
      }
    }
    return r_;
  }

 private:
  const std::vector<Piece> pieces_;
  const PathIndex index_;
  const ErrorFunction trueError_;
  NcRunReport r_;
  double sumSq_ = 0.0;
  std::array<double, 3> sumSqAxis_{};
};

}  // namespace

NcRunReport runNcProgram(const NcRunOptions& options) {
  const std::vector<NcProgramMove> program = readNcProgram(options.program);
  ContourMeter meter(options.reference, options.trueModel);
  double pathMm = 0.0;
  long markedMoves = 0;
  for (const NcProgramMove& m : program) {
    if (m.move.kind == nc::MoveKind::Rapid) continue;
    if (m.marked) {
      ++markedMoves;
      continue;
    }
    const double length = m.move.lengthMm();
    pathMm += length;
    const int n = piecesOf(m, length / options.stepMm, options.program.file, "samples at --step");
    const MotionDirections dirs = meter.directionsNear(m.move.at(0.5));
    for (int i = 0; i <= n; ++i) meter.add(m.move.at(static_cast<double>(i) / n), dirs);
  }
  NcRunReport r = meter.report();
  r.pathMm = pathMm;
  r.markedMoves = markedMoves;
  return r;
}

NcRunReport measureRecordedRun(const std::string& recordFile, const NcProgramSpec& reference,
                               const std::string& trueModel) {
  ContourMeter meter(reference, trueModel);
  std::ifstream in(recordFile);
  if (!in) throw config::ConfigError(recordFile, "", "cannot be read");
  std::string line;
  std::getline(in, line);
  if (line.rfind("x,y,z,ox,oy,oz", 0) != 0) {
    throw config::ConfigError(recordFile, "",
                              "expected the header x,y,z,ox,oy,oz, found " + config::quoted(line));
  }
  double pathMm = 0.0;
  std::optional<V3> previous;
  for (long row = 2; std::getline(in, line); ++row) {
    std::array<double, 6> f{};
    std::stringstream fields(line);
    std::string field;
    std::size_t k = 0;
    for (; k < f.size() && std::getline(fields, field, ','); ++k) {
      std::size_t used = 0;
      try {
        f[k] = std::stod(field, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || !std::isfinite(f[k])) {
        throw config::ConfigError(recordFile + ":" + std::to_string(row), "",
                                  "column " + std::to_string(k + 1) +
                                      ": expected a number, found " + config::quoted(field));
      }
    }
    if (k != f.size()) {
      throw config::ConfigError(recordFile + ":" + std::to_string(row), "",
                                "expected 6 numbers x,y,z,ox,oy,oz");
    }
    const V3 q(f[0] + f[3], f[1] + f[4], f[2] + f[5]);
    if (!(q.cwiseAbs().maxCoeff() <= nc::kMaxPositionMm)) {
      throw config::ConfigError(recordFile + ":" + std::to_string(row), "",
                                "a position beyond +-1e6 mm: is the unit wrong?");
    }
    if (previous) pathMm += (q - *previous).norm();
    previous = q;
    meter.add(q, meter.directionsNear(q));
  }
  NcRunReport r = meter.report();
  r.pathMm = pathMm;
  return r;
}

int ncRunMain(int argc, char** argv) {
  CLI::App app{
      "volcomp-sim nc-run: the simulated machine (its true error model) runs an NC program; the "
      "tool tip is compared with the path of a reference program (contour error), with no "
      "controller link. Original program as both: the error without compensation; a volcomp nc "
      "output against the original: the error with it.",
      "volcomp-sim nc-run"};
  NcRunOptions o;
  std::vector<double> start;
  std::string record;
  auto* program = app.add_option("program", o.program.file, "NC program the machine runs")
                      ->check(CLI::ExistingFile);
  auto* positions =
      app.add_option("--positions", record,
                     "Instead of a program: positions a machine recorded (CSV x,y,z,ox,oy,oz in "
                     "mm, one row per sample: axis positions and applied external offsets)")
          ->check(CLI::ExistingFile)
          ->excludes(program);
  program->excludes(positions);
  app.add_option("--reference", o.reference.file,
                 "Program whose path is the intended one (the original)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--model", o.trueModel, "The machine's true error model")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--work-offsets", o.program.workOffsets, ".var or .json work offsets (repeatable)")
      ->check(CLI::ExistingFile);
  app.add_option("--tool-table", o.program.toolTable, "LinuxCNC tool table")
      ->check(CLI::ExistingFile);
  app.add_option("--machine-units", o.program.machineUnits, "Units of .var/.tbl values")
      ->check(CLI::IsMember({"mm", "inch"}));
  app.add_option("--start", start, "Machine position at the start, X Y Z (mm)")->expected(3);
  app.add_option("--step", o.stepMm, "Sample spacing along the path (mm)")
      ->capture_default_str()
      ->check(CLI::Range(1e-4, 100.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (o.program.file.empty() && record.empty()) {
    std::cerr << "volcomp-sim nc-run: give a program or --positions\n";
    return 2;
  }
  if (start.size() == 3) o.program.startMm = Vec3{start[0], start[1], start[2]};
  const std::string file = o.reference.file;
  o.reference = o.program;
  o.reference.file = file;
  try {
    const NcRunReport r =
        record.empty() ? runNcProgram(o) : measureRecordedRun(record, o.reference, o.trueModel);
    std::cout << r.toJson().dump() << std::endl;
    std::cerr << "volcomp-sim nc-run: " << (record.empty() ? o.program.file : record) << " against "
              << o.reference.file << ": contour error RMS " << r.rmsUm << " um, max " << r.maxUm
              << " um (" << r.samples << " samples over " << r.pathMm << " mm)\n";
  } catch (const std::exception& e) {
    std::cerr << "volcomp-sim: " << e.what() << '\n';
    return 2;
  }
  return 0;
}

}  // namespace volcomp::sim
