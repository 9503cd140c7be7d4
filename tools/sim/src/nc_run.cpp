#include "volcomp/sim/nc_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <unordered_map>

#include <CLI/CLI.hpp>

#include "volcomp/config/config_error.hpp"
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
std::vector<Piece> referencePieces(const std::vector<NcProgramMove>& moves) {
  std::vector<Piece> pieces;
  MotionDirections dirs{};
  for (const NcProgramMove& m : moves) {
    int n = 1;
    if (m.move.kind == nc::MoveKind::Arc) {
      const double r = std::max(m.move.arc.startRadius, m.move.arc.endRadius);
      const double maxAngle = r > 1e-5 ? 2.0 * std::acos(1.0 - 1e-5 / r) : 1.0;
      n = std::max(1, static_cast<int>(std::ceil(std::abs(m.move.arc.sweep) / maxAngle)));
    }
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
  return nlohmann::json{{"samples", samples},
                        {"path_mm", pathMm},
                        {"rms_um", rmsUm},
                        {"max_um", maxUm},
                        {"rms_axis_um", rmsAxisUm},
                        {"max_axis_um", maxAxisUm},
                        {"marked_moves", markedMoves}};
}

NcRunReport runNcProgram(const NcRunOptions& options) {
  const std::vector<NcProgramMove> program = readNcProgram(options.program);
  const std::vector<NcProgramMove> reference = readNcProgram(options.reference);
  const std::vector<Piece> pieces = referencePieces(reference);
  if (pieces.empty()) {
    throw config::ConfigError(options.reference.file, "",
                              "the reference program has no feed moves");
  }
  const ErrorFunction trueError = loadTrueError(options.trueModel);
  const PathIndex index(pieces);
  NcRunReport r;
  double sumSq = 0.0;
  std::array<double, 3> sumSqAxis{};
  for (const NcProgramMove& m : program) {
    if (m.move.kind == nc::MoveKind::Rapid) continue;
    if (m.marked) {
      ++r.markedMoves;
      continue;
    }
    const double length = m.move.lengthMm();
    r.pathMm += length;
    const int n = std::max(1, static_cast<int>(std::ceil(length / options.stepMm)));
    const MotionDirections dirs = pieces[index.nearest(m.move.at(0.5))].dirs;
    for (int i = 0; i <= n; ++i) {
      const V3 q = m.move.at(static_cast<double>(i) / n);
      const Vec3 err = trueError({q[0], q[1], q[2]}, dirs);
      const V3 tip = q + V3(err[0], err[1], err[2]);
      const V3 error = tip - closestOn(pieces[index.nearest(tip)], tip);
      const double norm = error.norm() * 1000.0;
      sumSq += norm * norm;
      r.maxUm = std::max(r.maxUm, norm);
      for (std::size_t k = 0; k < 3; ++k) {
        const double c = error[static_cast<int>(k)] * 1000.0;
        sumSqAxis[k] += c * c;
        r.maxAxisUm[k] = std::max(r.maxAxisUm[k], std::abs(c));
      }
      ++r.samples;
    }
  }
  if (r.samples > 0) {
    r.rmsUm = std::sqrt(sumSq / static_cast<double>(r.samples));
    for (std::size_t k = 0; k < 3; ++k) {
      r.rmsAxisUm[k] = std::sqrt(sumSqAxis[k] / static_cast<double>(r.samples));
    }
  }
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
  app.add_option("program", o.program.file, "NC program the machine runs")
      ->required()
      ->check(CLI::ExistingFile);
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
  if (start.size() == 3) o.program.startMm = Vec3{start[0], start[1], start[2]};
  const std::string file = o.reference.file;
  o.reference = o.program;
  o.reference.file = file;
  try {
    const NcRunReport r = runNcProgram(o);
    std::cout << r.toJson().dump() << std::endl;
    std::cerr << "volcomp-sim nc-run: " << o.program.file << " against " << o.reference.file
              << ": contour error RMS " << r.rmsUm << " um, max " << r.maxUm << " um (" << r.samples
              << " samples over " << r.pathMm << " mm)\n";
  } catch (const std::exception& e) {
    std::cerr << "volcomp-sim: " << e.what() << '\n';
    return 2;
  }
  return 0;
}

}  // namespace volcomp::sim
