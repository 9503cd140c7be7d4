#include "eval_points.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "cli_support.hpp"
#include "points_csv.hpp"
#include "volcomp/config/csv_table.hpp"
#include "volcomp/output/output_file.hpp"

namespace volcomp::cli {
namespace {

constexpr std::size_t kProgressEvery = 100000;
constexpr std::size_t kFlushBytes = 1 << 20;

// One model per tool offset of the input (the model's own for rows without a tool column).
class ToolModels {
 public:
  explicit ToolModels(const model::MachineModel& model) : base_(model) {}
  const model::MachineModel& forTool(const Eigen::Vector3d& toolMm) {
    if (toolMm == base_.toolMm()) return base_;
    for (const auto& [tool, model] : models_) {
      if (tool == toolMm) return *model;
    }
    model::MachineModelSpec spec = base_.spec();
    spec.toolMm = toolMm;
    models_.emplace_back(toolMm, std::make_unique<model::MachineModel>(std::move(spec)));
    return *models_.back().second;
  }

 private:
  const model::MachineModel& base_;
  std::vector<std::pair<Eigen::Vector3d, std::unique_ptr<model::MachineModel>>> models_;
};

// The compute part: errors and compensation offsets of a chunk of rows through the model's batch
// paths (evaluateBatch, solveOffsetBatch: four points per SIMD register), then one output row per
// point. A chunk holds rows of one tool (a row with another tool flushes it first); directions
// are per row. The buffers are allocated once per file.
class PointsBatch {
 public:
  static constexpr std::size_t kCapacity = 4096;

  PointsBatch(model::EvalMode mode, bool writeTool, bool writeDirection)
      : mode_(mode), writeTool_(writeTool), writeDirection_(writeDirection) {
    options_.mode = mode;
    points_.reserve(kCapacity);
    lines_.reserve(kCapacity);
    directions_.reserve(kCapacity);
    errors_.resize(kCapacity);
    offsets_.resize(kCapacity);
  }

  bool full() const { return points_.size() == kCapacity; }
  /// The model of the rows added next; the caller flushes before changing it.
  bool sameModel(const model::MachineModel& model) const { return model_ == &model; }
  void setModel(const model::MachineModel& model) { model_ = &model; }
  void add(const Eigen::Vector3d& qMm, const model::Directions& directions, std::size_t line) {
    points_.push_back(qMm);
    directions_.push_back(directions);
    lines_.push_back(line);
  }

  /// Evaluates the rows added since the last flush, appends them to `out` and counts them in
  /// `summary`.
  void flush(std::string& out, PointsSummary& summary) {
    const std::size_t n = points_.size();
    if (n == 0) return;
    const std::span<const model::Directions> directions(directions_.data(), n);
    model::evaluateBatch(*model_, ws_, points_, std::span(errors_.data(), n), mode_, directions);
    model::solveOffsetBatch(*model_, ws_, points_, std::span(offsets_.data(), n), directions,
                            options_);
    const Eigen::Vector3d& toolMm = model_->toolMm();
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
      if (writeTool_) {
        for (double v : {toolMm.x(), toolMm.y(), toolMm.z()}) {
          appendDouble(out, v + 0.0);
          out += ',';
        }
      }
      if (writeDirection_) {
        for (model::Direction d : directions_[i]) {
          out += d == model::Direction::Positive   ? '+'
                 : d == model::Direction::Negative ? '-'
                                                   : '0';
        }
        out += ',';
      }
      out.back() = '\n';
    }
    points_.clear();
    directions_.clear();
    lines_.clear();
  }

 private:
  const model::MachineModel* model_ = nullptr;
  model::EvalMode mode_;
  bool writeTool_;
  bool writeDirection_;
  model::OffsetOptions options_;
  model::Workspace ws_;
  std::vector<model::Directions> directions_;
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
  std::ifstream in = config::CsvReader::open(inPath);
  config::CsvReader csv(in, inPath, pointsSchema());
  const int x = csv.column("x"), y = csv.column("y"), z = csv.column("z");
  const int tx = csv.column("tx"), ty = csv.column("ty"), tz = csv.column("tz");
  const int direction = csv.column("direction");

  // Prepared before the first row is evaluated: a bad --out fails at once, not after the work.
  output::OutputFile out(outPath, inputs);
  // The model file contract's twelve columns first; what the input adds per point after them.
  std::string buffer = "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz";
  if (tx >= 0) buffer += ",tx,ty,tz";
  if (direction >= 0) buffer += ",direction";
  buffer += '\n';
  buffer.reserve(kFlushBytes + 4096);
  const bool progress = isatty(STDERR_FILENO) == 1;
  ToolModels models(model);
  PointsBatch batch(mode, tx >= 0, direction >= 0);
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
  while (csv.next()) {
    const std::size_t lineNumber = csv.line();
    // One column after the other, so that a bad row names its first bad field (the order in
    // which a constructor's arguments are evaluated is unspecified).
    const auto vector = [&](int a, int b, int c) {
      Eigen::Vector3d v;
      v.x() = csv.number(a);
      v.y() = csv.number(b);
      v.z() = csv.number(c);
      return v;
    };
    const Eigen::Vector3d qMm = vector(x, y, z);
    const Eigen::Vector3d toolMm = tx >= 0 ? vector(tx, ty, tz) : model.toolMm();
    if (std::find(summary.toolsMm.begin(), summary.toolsMm.end(), toolMm) ==
        summary.toolsMm.end()) {
      summary.toolsMm.push_back(toolMm);
      summary.toolLines.push_back(lineNumber);
    }
    const model::MachineModel& toolModel = models.forTool(toolMm);
    if (!batch.sameModel(toolModel)) {
      flush();
      batch.setModel(toolModel);
    }
    batch.add(qMm, direction >= 0 ? csv.directions(direction) : directions, lineNumber);
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
