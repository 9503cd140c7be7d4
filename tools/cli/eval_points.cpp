#include "eval_points.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <span>
#include <string_view>
#include <vector>

#include "cli_support.hpp"
#include "volcomp/config/config_error.hpp"

namespace volcomp::cli {
namespace {

constexpr std::size_t kProgressEvery = 100000;
constexpr std::size_t kFlushBytes = 1 << 20;

std::string lineKey(std::size_t line) {
  return "line " + std::to_string(line);
}

std::string shown(std::string_view line) {
  std::string s(trim(line));
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return "\"" + s + "\"";
}

bool isHeader(std::string_view line) {
  if (line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);  // UTF-8 BOM from spreadsheets
  const std::vector<std::string_view> fields = splitFields(line);
  if (fields.size() != 3) return false;
  const char* names[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < 3; ++i) {
    if (fields[i].size() != 1 || (fields[i][0] | 0x20) != names[i][0]) return false;
  }
  return true;
}

class OutputFile {
 public:
  explicit OutputFile(const std::string& path) : path_(path), stream_(path, std::ios::binary) {
    if (!stream_) throw config::ConfigError(path, "", "cannot open for writing");
    buffer_.reserve(kFlushBytes + 4096);
  }
  ~OutputFile() {
    if (!committed_) {
      stream_.close();
      std::error_code ignored;
      std::filesystem::remove(path_, ignored);
    }
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  std::string& buffer() { return buffer_; }
  void flushIfLarge() {
    if (buffer_.size() >= kFlushBytes) flush();
  }
  void commit() {
    flush();
    stream_.close();
    if (!stream_) throw config::ConfigError(path_, "", "write failed");
    committed_ = true;
  }

 private:
  void flush() {
    stream_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    if (!stream_) throw config::ConfigError(path_, "", "write failed");
    buffer_.clear();
  }
  std::string path_;
  std::ofstream stream_;
  std::string buffer_;
  bool committed_ = false;
};

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
                                 const std::string& inPath, const std::string& outPath) {
  std::ifstream in(inPath, std::ios::binary);
  if (!in) throw config::ConfigError(inPath, "", "cannot open file");
  std::string line;
  std::size_t lineNumber = 0;
  bool haveHeader = false;
  while (!haveHeader && std::getline(in, line)) {
    ++lineNumber;
    if (trim(line).empty()) continue;
    if (!isHeader(line)) {
      throw config::ConfigError(inPath, lineKey(lineNumber),
                                "expected the header x,y,z, got " + shown(line));
    }
    haveHeader = true;
  }
  if (!haveHeader)
    throw config::ConfigError(inPath, "", "expected the header x,y,z, got an empty file");

  OutputFile out(outPath);
  out.buffer() += "x,y,z,ex,ey,ez,ea,eb,ec,ox,oy,oz\n";
  const bool progress = isatty(STDERR_FILENO) == 1;
  PointsBatch batch(model, directions, mode);
  PointsSummary summary;
  std::size_t lastProgress = 0;
  const auto flush = [&] {
    batch.flush(out.buffer(), summary);
    out.flushIfLarge();
    if (progress && summary.rows / kProgressEvery != lastProgress / kProgressEvery) {
      std::cerr << "\rvolcomp eval: " << summary.rows << " rows" << std::flush;
      lastProgress = summary.rows;
    }
  };
  while (std::getline(in, line)) {
    ++lineNumber;
    if (trim(line).empty()) continue;
    const std::vector<std::string_view> fields = splitFields(line);
    double q[3] = {0, 0, 0};
    bool ok = fields.size() == 3;
    for (std::size_t i = 0; ok && i < 3; ++i) ok = parseDouble(fields[i], q[i]);
    if (!ok) {
      throw config::ConfigError(inPath, lineKey(lineNumber),
                                "expected three finite numbers x,y,z (mm), got " + shown(line));
    }
    batch.add(Eigen::Vector3d(q[0], q[1], q[2]), lineNumber);
    if (batch.full()) flush();
  }
  flush();
  if (in.bad()) throw config::ConfigError(inPath, lineKey(lineNumber + 1), "read failed");
  out.commit();
  if (progress && summary.rows >= kProgressEvery) {
    std::cerr << "\rvolcomp eval: " << summary.rows << " rows, done\n";
  }
  return summary;
}

}  // namespace volcomp::cli
