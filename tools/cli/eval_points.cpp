#include "eval_points.hpp"

#include <unistd.h>

#include <fstream>
#include <iostream>
#include <span>
#include <vector>

#include "cli_support.hpp"
#include "points_csv.hpp"
#include "volcomp/config/text_input.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

constexpr std::size_t kProgressEvery = 100000;
constexpr std::size_t kFlushBytes = 1 << 20;

// The compute part: errors and compensation offsets of a chunk of rows through the model's batch
// paths (evaluateBatch, solveOffsetBatch: four points per SIMD register), then one output row per
// point. The buffers are allocated once per file.
class PointsBatch {
 public:
  static constexpr std::size_t kCapacity = 4096;

  PointsBatch(const model::MachineModel& model, const model::Directions& directions,
              model::EvalMode mode)
      : model_(model), mode_(mode), directions_(kCapacity, directions) {
    options_.mode = mode;
    points_.reserve(kCapacity);
    lines_.reserve(kCapacity);
    errors_.resize(kCapacity);
    offsets_.resize(kCapacity);
  }

  bool full() const { return points_.size() == kCapacity; }
  void add(const Eigen::Vector3d& qMm, std::size_t line) {
    points_.push_back(qMm);
    lines_.push_back(line);
  }

  /// Evaluates the rows added since the last flush, appends them to `out` and counts them in
  /// `summary`.
  void flush(std::string& out, PointsSummary& summary) {
    const std::size_t n = points_.size();
    const std::span<const model::Directions> directions(directions_.data(), n);
    model::evaluateBatch(model_, ws_, points_, std::span(errors_.data(), n), mode_, directions);
    model::solveOffsetBatch(model_, ws_, points_, std::span(offsets_.data(), n), directions,
                            options_);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d& q = points_[i];
      const model::PointError& e = errors_[i];
      const model::OffsetSolution& o = offsets_[i];
      ++summary.rows;
      if (e.clampedAxes != 0 && summary.clampedRows++ == 0) summary.firstClampedLine = lines_[i];
      if (!o.converged && summary.notConvergedRows++ == 0) {
        summary.firstNotConvergedLine = lines_[i];
      }
      for (double v : {q.x(), q.y(), q.z(), e.errorMm.x(), e.errorMm.y(), e.errorMm.z(),
                       e.angularErrorRad.x(), e.angularErrorRad.y(), e.angularErrorRad.z(),
                       o.offsetMm.x(), o.offsetMm.y(), o.offsetMm.z()}) {
        appendDouble(out, v + 0.0);  // + 0.0 turns -0 into 0
        out += ',';
      }
      out.back() = '\n';
    }
    points_.clear();
    lines_.clear();
  }

 private:
  const model::MachineModel& model_;
  model::EvalMode mode_;
  model::OffsetOptions options_;
  model::Workspace ws_;
  std::vector<model::Directions> directions_;  // the same for every row
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::size_t> lines_;
  std::vector<model::PointError> errors_;
  std::vector<model::OffsetSolution> offsets_;
};

}  // namespace

PointsSummary evaluatePointsFile(const model::MachineModel& model,
                                 const model::Directions& directions, model::EvalMode mode,
                                 const std::string& inPath, const std::string& outPath,
                                 const std::vector<std::string>& otherInputs) {
  std::vector<std::filesystem::path> inputs{inPath};
  inputs.insert(inputs.end(), otherInputs.begin(), otherInputs.end());
  std::ifstream in = config::openTextFile(inPath);
  PointsCsvReader reader(in, inPath);
  // Prepared before the first row is evaluated: a bad --out fails at once, not after the work.
  output::OutputFile out(outPath, inputs);
  std::string buffer = "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz\n";
  buffer.reserve(kFlushBytes + 4096);
  const bool progress = isatty(STDERR_FILENO) == 1;
  PointsBatch batch(model, directions, mode);
  PointsSummary summary;
  std::size_t lastProgress = 0;
  const auto flush = [&] {
    batch.flush(buffer, summary);
    if (buffer.size() >= kFlushBytes) {
      out.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
    if (progress && summary.rows / kProgressEvery != lastProgress / kProgressEvery) {
      std::cerr << "\rvolcomp eval: " << summary.rows << " rows" << std::flush;
      lastProgress = summary.rows;
    }
  };
  Eigen::Vector3d qMm;
  while (reader.next(qMm)) {
    batch.add(qMm, reader.lineNumber());
    if (batch.full()) flush();
  }
  flush();
  out.stream().write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  out.commit();
  if (progress && summary.rows >= kProgressEvery) {
    std::cerr << "\rvolcomp eval: " << summary.rows << " rows, done\n";
  }
  return summary;
}

}  // namespace volcomp::cli
